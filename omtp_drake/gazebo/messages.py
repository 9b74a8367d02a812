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
from dataclasses import dataclass
from typing import Any

from pydrake.math import RigidTransform


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


@dataclass(frozen=True)
class EntityStates:
    """Gazebo's entities' states: ``name``, ``pose`` ``X_WE`` and ``twist`` (vx, vy, vz, wx, wy,
    wz) of each, in the world frame (``gazebo_msgs`` has no header: ``stamp`` is when it was
    made)."""

    stamp: float
    name: tuple[str, ...]
    pose: tuple[RigidTransform, ...]
    twist: tuple[tuple[float, ...], ...]


@dataclass(frozen=True)
class ModelStates(EntityStates):
    """``gazebo_msgs/ModelStates``: every model in the world."""


@dataclass(frozen=True)
class LinkStates(EntityStates):
    """``gazebo_msgs/LinkStates``: every link (``model::link``) of the models in the world."""


@dataclass(frozen=True)
class SpawnedPart:
    """The course's spawner's ``/spawned_part`` (``std_msgs/Header``): ``seq`` the spawner's
    count (ROS 1 only: ROS 2's Header has none), ``frame_id`` the drawn object's name."""

    stamp: float
    frame_id: str
    seq: int
