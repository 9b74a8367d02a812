"""A ``trajectory_msgs/JointTrajectory`` as the cell reads it, from either transport: the one
request type of every plugin and controller that takes one (gazebo_ros's joint pose
trajectory plugin, ros_control's and ros2_control's trajectory controllers).

Times are simulated seconds (float): :func:`trajectory_request` reads a transport's message
with that transport's own time conversion, once. What a request's fields mean, and what a
bad one gets, is each receiver's rule (:mod:`omtp_drake.gazebo.joint_pose_trajectory`,
:mod:`omtp_drake.sim.ros_control`), not this module's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class RequestPoint:
    """A ``trajectory_msgs/JointTrajectoryPoint``: its ``time_from_start`` (s) and values."""

    time_from_start: float
    positions: tuple[float, ...]
    velocities: tuple[float, ...] = ()
    accelerations: tuple[float, ...] = ()


@dataclass(frozen=True)
class TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory``: joint names, points, ``header.stamp`` (s) and
    ``header.frame_id``."""

    joint_names: tuple[str, ...]
    points: tuple[RequestPoint, ...] = ()
    stamp: float = 0.0
    frame_id: str = ""


def trajectory_request(message: Any, seconds: Callable[[Any], float]) -> TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory`` of either transport as a request; ``seconds``
    turns its time and durations into seconds (each transport's own time type)."""
    points = tuple(
        RequestPoint(
            seconds(p.time_from_start),
            tuple(map(float, p.positions)),
            tuple(map(float, p.velocities)),
            tuple(map(float, p.accelerations)),
        )
        for p in message.points
    )
    header = message.header
    return TrajectoryRequest(tuple(message.joint_names), points, seconds(header.stamp), header.frame_id)
