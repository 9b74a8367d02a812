"""``/set_joint_trajectory``: joints set (not driven) to a trajectory's points, as
Gazebo's ``gazebo_ros_joint_pose_trajectory`` plugin of the URDF tutorial does.

The plugin's rules, kept here:

- ``header.frame_id`` names the reference link: ``world`` or ``map``, or a link of
  the model, which stays where it is. Anything else (empty too) is refused and the
  trajectory is not set. The cell's arms stand on their pedestals, so a link is
  accepted when it is welded to the world (the joints cannot move it); a link the
  joints move would need the arm's base to move, which the cell refuses.
- every name of ``joint_names`` must be a joint of the cell, else the trajectory
  is not set ("Joint [x] not found");
- the trajectory starts at ``header.stamp``, or now when that has passed (a zero
  stamp: now). Point 0 is set at the start; point i+1 is set ``time_from_start``
  of point i after point i (the plugin adds each point's ``time_from_start`` to its
  start time after setting the point);
- a point whose number of positions differs from the number of joints is skipped
  with an error; a new trajectory replaces the one being played.

Setting a point puts the named joints there at once (a teleport, with
:meth:`~omtp_drake.script.arm.Arm.set_joint_values`), the arm's other joints stay,
and the arm's servo holds the new position afterwards.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from omtp_drake.errors import ConfigError, UnknownNameError

#: The reference frames that mean "the world" to the plugin.
WORLD_FRAMES = ("world", "map")


@dataclass(frozen=True)
class JointPoint:
    """One point of a trajectory: when it is due (s, simulated) and where each named
    joint goes (None: the point has the wrong number of positions)."""

    time: float
    positions: Optional[tuple[float, ...]]


@dataclass(frozen=True)
class JointPoseTrajectory:
    """A trajectory as the plugin plays it: the joints (arm, index in the arm) and
    the points with the times they are due."""

    joint_names: tuple[str, ...]
    joints: tuple[tuple[str, int], ...]
    points: tuple[JointPoint, ...]


def parse_trajectory(
    msg: Any, now: float, joints: dict[str, tuple[str, int]], fixed_links: set[str]
) -> JointPoseTrajectory:
    """The trajectory a ``trajectory_msgs/JointTrajectory`` asks for, received at
    ``now``; ``joints`` maps the cell's joint names to (arm, index), ``fixed_links``
    are the links that no joint moves.

    Raises:
        ConfigError: the reference link is not one the cell accepts (see the module doc).
        UnknownNameError: a joint name the cell does not have.
    """
    frame = msg.header.frame_id
    if frame not in WORLD_FRAMES and frame not in fixed_links:
        raise ConfigError(
            f"set_joint_trajectory needs a reference link as header.frame_id, got {frame!r}; valid: "
            f"{', '.join(WORLD_FRAMES)} or a link fixed to the world (e.g. an arm's base_link)"
        )
    for name in msg.joint_names:
        if name not in joints:
            raise UnknownNameError("joint", name, joints)
    start = max(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9, now)
    points = []
    for point in msg.points:
        ok = len(point.positions) == len(msg.joint_names)
        points.append(JointPoint(start, tuple(float(x) for x in point.positions) if ok else None))
        start += point.time_from_start.sec + point.time_from_start.nanosec * 1e-9
    return JointPoseTrajectory(
        tuple(msg.joint_names), tuple(joints[n] for n in msg.joint_names), tuple(points)
    )


def arm_targets(
    trajectory: JointPoseTrajectory, positions: tuple[float, ...], current: dict[str, np.ndarray]
) -> dict[str, np.ndarray]:
    """Arm -> its joint positions with ``positions`` set on the trajectory's joints
    (the others as in ``current``, each arm's positions now)."""
    targets: dict[str, np.ndarray] = {}
    for (arm, index), q in zip(trajectory.joints, positions):
        targets.setdefault(arm, np.array(current[arm], dtype=float))[index] = q
    return targets
