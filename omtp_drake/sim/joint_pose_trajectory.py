"""gazebo_ros's joint pose trajectory plugin on a running cell: a world edit that sets joints.

``libgazebo_ros_joint_pose_trajectory.so`` is no controller: given a
``trajectory_msgs/JointTrajectory`` it *sets* the named joints of its model to each
point's positions, one point per update (at most ``update_rate`` times a second), and
lets physics go on from there (the joints are not held: gravity and the joints'
damping act on them afterwards, as in Gazebo). Timing as the plugin's: the trajectory
starts at its ``header.stamp`` (now if that is past); a point is applied at the first
update at or after the start, and the start then moves on by that point's
``time_from_start`` (the plugin adds each point's time to the previous start). A new
trajectory replaces the one playing. A point whose number of positions differs from the
joints' is skipped with the plugin's error (its time still counts). The velocities of
the set joints are zeroed (Gazebo keeps the links' world velocities; here the set pose starts at rest).

A world edit (:class:`omtp_drake.sim.driver.WorldEdit`): the driver calls it every
``1 / update_rate`` seconds of simulated time.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from pydrake.multibody.tree import Joint
from pydrake.systems.framework import Context

from omtp_drake.scenario.gazebo_tags import JointPoseTrajectoryPlugin

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

_EPS = 1e-9
_log = logging.getLogger("gazebo")


@dataclass(frozen=True)
class PosePoint:
    """One point: the joints' positions and its ``time_from_start`` (s)."""

    positions: tuple[float, ...]
    time_from_start: float


class JointPoseTrajectory:
    """The plugin ``config`` of model ``model`` on ``station`` (see the module doc)."""

    def __init__(self, station: Station, model: str, config: JointPoseTrajectoryPlugin):
        self._station = station
        self.model = model
        self.config = config
        self.period = 1.0 / config.update_rate
        self._joints: list[Joint] = []
        self._points: list[PosePoint] = []
        self._start = math.inf
        self._index = 0
        #: How many points were applied (all trajectories).
        self.applied = 0

    def joint_names(self) -> list[str]:
        """The model's joints that have one position (the ones a trajectory may set)."""
        plant = self._station.plant
        joints = [plant.get_joint(j) for j in plant.GetJointIndices(self._station.models[self.model])]
        return [j.name() for j in joints if j.num_positions() == 1]

    def set_trajectory(
        self, joint_names: Sequence[str], points: Sequence[PosePoint], stamp: float, now: float
    ) -> None:
        """Plays ``points`` for ``joint_names`` (joints of the model, checked by the
        plugin: :mod:`omtp_drake.gazebo.joint_pose_trajectory`) from ``stamp`` (now if
        past), replacing what plays."""
        plant = self._station.plant
        instance = self._station.models[self.model]
        self._joints = [plant.GetJointByName(name, instance) for name in joint_names]
        self._points = list(points)
        self._start = max(stamp, now)
        self._index = 0

    @property
    def playing(self) -> bool:
        return self._index < len(self._points)

    def __call__(self, root_context: Context) -> None:
        if not self.playing or root_context.get_time() < self._start - _EPS:
            return
        point = self._points[self._index]
        self._start += point.time_from_start
        self._index += 1
        if len(point.positions) != len(self._joints):
            _log.error(
                "%s: point[%d] has different number of joint names[%d] and positions[%d]; skipped",
                self.config.name,
                self._index,
                len(self._joints),
                len(point.positions),
            )
            return
        plant = self._station.plant
        plant_context = plant.GetMyMutableContextFromRoot(root_context)
        q, v = plant.GetPositions(plant_context), plant.GetVelocities(plant_context)
        for joint, position in zip(self._joints, point.positions):
            q[joint.position_start()] = position
            v[joint.velocity_start()] = 0.0
        plant.SetPositions(plant_context, q)
        plant.SetVelocities(plant_context, v)
        self.applied += 1


def joint_pose_trajectories(station: Station) -> list[JointPoseTrajectory]:
    """One world edit per joint pose trajectory plugin of the station's models."""
    return [
        JointPoseTrajectory(station, model.name, plugin)
        for model in station.scenario.models
        for plugin in model.gazebo.joint_pose_trajectories
    ]
