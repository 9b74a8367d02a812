"""The messages of the Gazebo plugin layer, free of any middleware: each transport maps
them field for field onto its own type (``sensor_msgs/JointState`` and so on).

Fields are named as the ROS 2 message's (``sensor_msgs/msg/JointState``...), ``stamp`` and
``frame_id`` standing for the header: :func:`message_fields` gives a transport the rest to
pass on. Stamps are simulated seconds (float); a transport converts them to its time
type once. Image data is the bytes of the ROS message's ``data`` field, laid out as the
encoding says (REP 118), so a transport copies it as it is.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class JointStates:
    """``sensor_msgs/JointState``: the named joints' positions (and velocities, when the
    plugin reports them)."""

    stamp: float
    name: tuple[str, ...]
    position: tuple[float, ...]
    velocity: tuple[float, ...] = ()
    frame_id: str = ""


@dataclass(frozen=True)
class Image:
    """``sensor_msgs/Image``."""

    stamp: float
    frame_id: str
    height: int
    width: int
    encoding: str
    step: int
    data: bytes
    is_bigendian: int = 0


@dataclass(frozen=True)
class CameraInfo:
    """``sensor_msgs/CameraInfo`` (row-major ``k`` 3x3, ``r`` 3x3, ``p`` 3x4)."""

    stamp: float
    frame_id: str
    height: int
    width: int
    distortion_model: str
    d: tuple[float, ...]
    k: tuple[float, ...]
    r: tuple[float, ...]
    p: tuple[float, ...]


@dataclass(frozen=True)
class CloudField:
    """A ``sensor_msgs/PointField``: every field here is one FLOAT32."""

    name: str
    offset: int


@dataclass(frozen=True)
class PointCloud:
    """``sensor_msgs/PointCloud2`` of FLOAT32 fields."""

    stamp: float
    frame_id: str
    height: int
    width: int
    fields: tuple[CloudField, ...]
    point_step: int
    row_step: int
    data: bytes
    is_dense: bool
    is_bigendian: bool = False


@dataclass(frozen=True)
class TrajectoryPoint:
    """A ``trajectory_msgs/JointTrajectoryPoint``'s positions and ``time_from_start`` (s)."""

    positions: tuple[float, ...]
    time_from_start: float


@dataclass(frozen=True)
class TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory`` as a joint pose trajectory plugin reads it."""

    frame_id: str
    stamp: float
    joint_names: tuple[str, ...]
    points: tuple[TrajectoryPoint, ...] = field(default_factory=tuple)


def message_fields(message: Any) -> dict[str, Any]:
    """The ROS message's fields of a published ``message`` but its header (``stamp``,
    ``frame_id``): sequences as lists, a cloud's fields as (name, offset) pairs."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(message):
        if f.name in ("stamp", "frame_id"):
            continue
        value = getattr(message, f.name)
        if f.name == "fields":
            value = [(c.name, c.offset) for c in value]
        elif isinstance(value, tuple):
            value = list(value)
        out[f.name] = value
    return out


def trajectory_request(msg: Any, seconds: Callable[[Any], float]) -> TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory`` of either transport as a request; ``seconds``
    reads that transport's time and duration."""
    points = tuple(
        TrajectoryPoint(tuple(float(q) for q in p.positions), seconds(p.time_from_start)) for p in msg.points
    )
    return TrajectoryRequest(msg.header.frame_id, seconds(msg.header.stamp), tuple(msg.joint_names), points)
