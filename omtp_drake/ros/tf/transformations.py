"""The few helpers of ROS's ``tf.transformations`` that course scripts use.

Quaternions are ``[x, y, z, w]`` lists as in ``tf.transformations``; Euler
angles are only the static x-y-z convention (``axes='sxyz'``, ROS's roll,
pitch, yaw); other conventions raise NotSupportedError.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.common.eigen_geometry import Quaternion as DrakeQuaternion
from pydrake.math import RollPitchYaw, RotationMatrix

from omtp_drake.ros.comm.messages import Quaternion
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.tf.convert import unit_quaternion


def _axes(axes: str) -> None:
    if axes != "sxyz":
        not_supported(f"tf.transformations with axes={axes!r}", "only 'sxyz' (roll, pitch, yaw)")


def _drake(q: Sequence[float]) -> DrakeQuaternion:
    x, y, z, w = (float(v) for v in q)
    return unit_quaternion(Quaternion(x, y, z, w), "tf.transformations")


def _xyzw(q: DrakeQuaternion) -> list[float]:
    return [float(q.x()), float(q.y()), float(q.z()), float(q.w())]


def quaternion_from_euler(ai: float, aj: float, ak: float, axes: str = "sxyz") -> list[float]:
    _axes(axes)
    return _xyzw(RollPitchYaw(ai, aj, ak).ToQuaternion())


def euler_from_quaternion(quaternion: Sequence[float], axes: str = "sxyz") -> tuple[float, float, float]:
    _axes(axes)
    r, p, y = RollPitchYaw(_drake(quaternion)).vector()
    return float(r), float(p), float(y)


def quaternion_multiply(quaternion1: Sequence[float], quaternion0: Sequence[float]) -> list[float]:
    x1, y1, z1, w1 = (float(v) for v in quaternion1)
    x0, y0, z0, w0 = (float(v) for v in quaternion0)
    return [
        w1 * x0 + x1 * w0 + y1 * z0 - z1 * y0,
        w1 * y0 - x1 * z0 + y1 * w0 + z1 * x0,
        w1 * z0 + x1 * y0 - y1 * x0 + z1 * w0,
        w1 * w0 - x1 * x0 - y1 * y0 - z1 * z0,
    ]


def quaternion_conjugate(quaternion: Sequence[float]) -> list[float]:
    x, y, z, w = (float(v) for v in quaternion)
    return [-x, -y, -z, w]


def quaternion_inverse(quaternion: Sequence[float]) -> list[float]:
    q = np.asarray(quaternion_conjugate(quaternion))
    return [float(v) for v in q / float(np.dot(q, q))]


def quaternion_matrix(quaternion: Sequence[float]) -> np.ndarray:
    """The 4x4 homogeneous rotation matrix of a quaternion."""
    M = np.eye(4)
    M[:3, :3] = RotationMatrix(_drake(quaternion)).matrix()
    return M


def euler_matrix(ai: float, aj: float, ak: float, axes: str = "sxyz") -> np.ndarray:
    _axes(axes)
    M = np.eye(4)
    M[:3, :3] = RollPitchYaw(ai, aj, ak).ToRotationMatrix().matrix()
    return M


def quaternion_from_matrix(matrix: Sequence[Sequence[float]]) -> list[float]:
    R = np.asarray(matrix, dtype=float)[:3, :3]
    return _xyzw(RotationMatrix(R).ToQuaternion())


def translation_matrix(direction: Sequence[float]) -> np.ndarray:
    M = np.eye(4)
    M[:3, 3] = np.asarray(direction, dtype=float)[:3]
    return M


def translation_from_matrix(matrix: Sequence[Sequence[float]]) -> np.ndarray:
    return np.array(matrix, dtype=float)[:3, 3].copy()
