"""Between ROS geometry messages and Drake's RigidTransform (X_AB: pose of B in A)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from pydrake.common.eigen_geometry import Quaternion as DrakeQuaternion
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm.messages import Message, Point, Pose, Quaternion, Transform, Vector3


def pose_msg(X: RigidTransform) -> Message:
    """``X`` as a geometry_msgs/Pose (plain floats by ``tolist``: every model of every
    published model and link state, at each physics update)."""
    x, y, z = X.translation().tolist()
    w, qx, qy, qz = X.rotation().ToQuaternion().wxyz().tolist()
    return Pose(Point(x, y, z), Quaternion(qx, qy, qz, w))


def transform_msg(X: RigidTransform) -> Message:
    """``X`` as a geometry_msgs/Transform."""
    pose = pose_msg(X)
    p, q = pose.position, pose.orientation
    return Transform(Vector3(p.x, p.y, p.z), Quaternion(q.x, q.y, q.z, q.w))


def unit_quaternion(q: Any, what: str) -> DrakeQuaternion:
    """The rotation of a quaternion ``q`` (with ``x, y, z, w``), normalized; ConfigError
    naming ``what`` when it is not finite or near zero."""
    wxyz = np.array([q.w, q.x, q.y, q.z], dtype=float)
    norm = float(np.linalg.norm(wxyz))
    if not np.all(np.isfinite(wxyz)) or norm < 1e-6:
        xyzw = tuple(wxyz[[1, 2, 3, 0]].tolist())
        raise ConfigError(
            f"{what}: the orientation quaternion (x, y, z, w) = {xyzw} is not a "
            "rotation; a ROS Quaternion is all zeros by default: set w = 1 for no rotation"
        )
    return DrakeQuaternion(wxyz / norm)


def rigid(msg: Any, what: str = "pose") -> RigidTransform:
    """A Pose or Transform message as a RigidTransform (the quaternion normalized)."""
    if isinstance(msg, Pose):
        p, q = msg.position, msg.orientation
    elif isinstance(msg, Transform):
        p, q = msg.translation, msg.rotation
    else:
        raise ConfigError(f"{what} must be a geometry_msgs Pose or Transform, got {type(msg).__name__}")
    xyz = np.array([p.x, p.y, p.z], dtype=float)
    if not np.all(np.isfinite(xyz)):
        raise ConfigError(f"{what}: the position {xyz.tolist()} is not finite")
    return RigidTransform(unit_quaternion(q, what), xyz)


def pose_from_list(values: Sequence[float], what: str = "pose") -> RigidTransform:
    """MoveIt's list form: ``[x, y, z, roll, pitch, yaw]`` or ``[x, y, z, qx, qy, qz, qw]``."""
    v = np.asarray(values, dtype=float).reshape(-1)
    if v.shape == (6,):
        return RigidTransform(RollPitchYaw(v[3:]), v[:3])
    if v.shape == (7,):
        q = Quaternion(*v[3:])
        return RigidTransform(unit_quaternion(q, what), v[:3])
    raise ConfigError(
        f"{what} as a list takes 6 numbers (x, y, z, roll, pitch, yaw) or 7 (x, y, z, qx, qy, qz, qw), "
        f"got {len(v)}"
    )


def pose_to_list(pose: Message) -> list[float]:
    """moveit_commander.conversions.pose_to_list: ``[x, y, z, qx, qy, qz, qw]``."""
    p, q = pose.position, pose.orientation
    return [p.x, p.y, p.z, q.x, q.y, q.z, q.w]


def list_to_pose(values: Sequence[float]) -> Message:
    """moveit_commander.conversions.list_to_pose (6 or 7 numbers, as pose_from_list)."""
    return pose_msg(pose_from_list(values))
