"""Between the cell's timed plans and ``moveit_msgs/RobotTrajectory``.

A plan becomes a RobotTrajectory with one point per knot of its joint
trajectory (positions, velocities, accelerations, time from start). Executing a
RobotTrajectory this module made, unchanged, runs the exact plan; a changed or
hand-made one is interpolated through its points (cubic Hermite with the
points' velocities, or straight segments without them).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import JOINT_NAMES, Plan
from omtp_drake.ros.comm.interfaces import RobotTrajectory
from omtp_drake.ros.comm.messages import (
    Duration,
    Header,
    JointTrajectory,
    JointTrajectoryPoint,
    Message,
    Time,
)

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session

#: How many recent plans keep their exact trajectory for execution.
_CACHE_SIZE = 32


def joint_names(robot: str) -> list[str]:
    """The arm's joint names in the plant (``robot2_shoulder_pan_joint``...)."""
    return [f"{robot}_{name}" for name in JOINT_NAMES]


def _fingerprint(msg: Message) -> tuple:
    points = msg.joint_trajectory.points
    return tuple(joint_names_tuple(msg)) + tuple(
        (p.time_from_start.to_nsec(), tuple(p.positions), tuple(p.velocities)) for p in points
    )


def joint_names_tuple(msg: Message) -> tuple[str, ...]:
    return tuple(msg.joint_trajectory.joint_names)


def to_msg(plan: Plan, robot: str, session: Session) -> Message:
    """``plan`` as a RobotTrajectory (remembered, so executing it runs ``plan`` exactly)."""
    trajectory = plan.trajectory
    t0 = trajectory.start_time()
    points = []
    for t in trajectory.get_segment_times():
        points.append(
            JointTrajectoryPoint(
                positions=[float(x) for x in trajectory.value(t).ravel()],
                velocities=[float(x) for x in trajectory.EvalDerivative(t, 1).ravel()],
                accelerations=[float(x) for x in trajectory.EvalDerivative(t, 2).ravel()],
                time_from_start=Duration(t - t0),
            )
        )
    header = Header(stamp=Time(session.time), frame_id="world")
    msg = RobotTrajectory(
        joint_trajectory=JointTrajectory(header=header, joint_names=joint_names(robot), points=points)
    )
    cache = session.plans
    cache[id(msg)] = (msg, _fingerprint(msg), plan)
    while len(cache) > _CACHE_SIZE:
        cache.popitem(last=False)
    return msg


def from_msg(msg: Any, robot: str, session: Session) -> Plan:
    """The plan a RobotTrajectory stands for (see the module doc)."""
    if isinstance(msg, tuple):
        raise ConfigError(
            "execute takes a RobotTrajectory; plan() of MoveIt Noetic returns (success, trajectory, "
            "planning_time, error_code): execute(plan[1])"
        )
    if not isinstance(msg, RobotTrajectory):
        raise ConfigError(f"execute takes a moveit_msgs RobotTrajectory, got {type(msg).__name__}")
    cached = session.plans.get(id(msg))
    if cached is not None and cached[0] is msg and cached[1] == _fingerprint(msg):
        return cached[2]
    names = list(msg.joint_trajectory.joint_names)
    expected = joint_names(robot)
    if sorted(names) != sorted(expected):
        raise ConfigError(f"the trajectory's joints {names} are not {robot}'s: {expected}")
    order = [names.index(n) for n in expected]
    points = msg.joint_trajectory.points
    if not points:
        raise ConfigError("the trajectory has no points (an empty plan: planning failed?)")
    times = np.array([p.time_from_start.to_sec() for p in points])
    if np.any(np.diff(times) <= 0):
        raise ConfigError(f"the trajectory's times from start must increase, got {times.tolist()}")
    q = np.array([[p.positions[i] for i in order] for p in points]).T
    if len(points) == 1:
        trajectory = PiecewisePolynomial.FirstOrderHold([times[0], times[0] + 1e-3], np.hstack([q, q]))
    elif all(len(p.velocities) == len(expected) for p in points):
        v = np.array([[p.velocities[i] for i in order] for p in points]).T
        trajectory = PiecewisePolynomial.CubicHermite(times, q, v)
    else:
        trajectory = PiecewisePolynomial.FirstOrderHold(times, q)
    return Plan(trajectory, tuple(q.T), "joint")
