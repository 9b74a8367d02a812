"""``gazebo_ros_joint_pose_trajectory``: what a ``trajectory_msgs/JointTrajectory`` on
``<ns>/set_joint_trajectory`` gets (the plugin's default topic and rate, 100 Hz; the
tutorial's ``<update_rate>`` is read once with the model's tags).

The request's rules, as both branches of gazebo_ros_pkgs apply them when a message comes:

- ``header.frame_id`` names the reference link: ``world`` or ``map`` (ROS 1 also
  ``/map``) mean the world; any other name must be a link, which stays where it is while
  the joints are set. Here that link must be welded to the world (a link the joints
  move would need the model's base to move, which the cell does not do). Anything else,
  the empty string too, is refused: "needs a reference link [x] as frame_id", and
  nothing changes.
- every name of ``joint_names`` must be a joint of the plugin's model, else "Joint [x]
  not found. Trajectory not set." and nothing changes;
- otherwise the trajectory replaces the one playing and starts at ``header.stamp``, or
  now when that has passed.

How the points are then played (one point per update, the start moving on by each
point's ``time_from_start``; a point whose number of positions differs from the joints'
is skipped with the plugin's error; the joints set, not held) is the world edit's,
:mod:`omtp_drake.sim.joint_pose_trajectory`, called by the driver at the plugin's rate.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from omtp_drake.errors import ConfigError
from omtp_drake.gazebo.schedule import Subscription, topic
from omtp_drake.sim.joint_pose_trajectory import JointPoseTrajectory, PosePoint
from omtp_drake.sim.trajectory_request import TrajectoryRequest

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The reference frames that mean "the world" to the plugin.
WORLD_REFERENCES = ("world", "map", "/map")

_log = logging.getLogger("gazebo")


class TrajectoryPlugin:
    """The plugin ``edit`` (the driver's world edit of one model's plugin) on ``cell``."""

    def __init__(self, cell: Cell, edit: JointPoseTrajectory):
        self._cell = cell
        self.edit = edit
        plant = cell.station.plant
        self._fixed_links = {b.name() for b in plant.GetBodiesWeldedTo(plant.world_body())}
        self.topic = topic(edit.config.namespace, edit.config.topic)

    def check(self, request: TrajectoryRequest) -> None:
        """Raises ConfigError with the plugin's message when it refuses ``request``."""
        frame = request.frame_id
        if frame not in WORLD_REFERENCES and frame not in self._fixed_links:
            raise ConfigError(
                f"needs a reference link [{frame}] as frame_id; valid: {', '.join(WORLD_REFERENCES[:2])} "
                "or a link fixed to the world"
            )
        known = self.edit.joint_names()
        for name in request.joint_names:
            if name not in known:
                raise ConfigError(f"Joint [{name}] not found; valid: {', '.join(known)}")

    def receive(self, request: TrajectoryRequest) -> bool:
        """Plays ``request`` from its stamp (now if past), or logs why not (the plugin's
        error line) and leaves what plays. True when it was taken."""
        try:
            self.check(request)
        except ConfigError as e:
            _log.error("%s: %s. Trajectory not set.", self.edit.config.name, e)
            return False
        points = [PosePoint(p.positions, p.time_from_start) for p in request.points]
        self.edit.set_trajectory(request.joint_names, points, request.stamp, self._cell.time)
        return True

    def subscription(self) -> Subscription:
        return Subscription(self.topic, TrajectoryRequest, self.receive, plugin=self.edit.config.name)


def trajectory_plugins(cell: Cell) -> list[TrajectoryPlugin]:
    """The joint pose trajectory plugins of ``cell``'s models (their world edits)."""
    return [
        TrajectoryPlugin(cell, e) for e in cell.runtime.driver.edits if isinstance(e, JointPoseTrajectory)
    ]
