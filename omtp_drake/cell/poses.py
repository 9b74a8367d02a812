"""Stamped poses and transforms, as in ROS's geometry_msgs and tf2.

``TransformStamped`` / ``PoseStamped`` carry a frame name and a time with a
:class:`~pydrake.math.RigidTransform`; ``interpolate_pose`` blends two poses;
``detected_frame_name`` names the frame of a model a logical camera sees.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from pydrake.math import RigidTransform


@dataclass(frozen=True)
class TransformStamped:
    """tf2's ``TransformStamped``: the pose of ``child_frame_id`` in ``header_frame_id``.

    Attributes:
        header_frame_id: the target frame T.
        child_frame_id: the source frame S.
        time: the time of the transform [s] (simulated time).
        transform: ``X_TS``.
    """

    header_frame_id: str
    child_frame_id: str
    time: float
    transform: RigidTransform


@dataclass(frozen=True)
class PoseStamped:
    """tf2's ``PoseStamped``: ``pose`` is X_FP, the pose of something P in ``frame_id`` F.

    ``time=None`` means the latest time the buffer has.
    """

    frame_id: str
    time: Optional[float]
    pose: RigidTransform


def detected_frame_name(camera: str, model: str) -> str:
    """The frame of a model a camera sees: ``<camera>_<model>_frame``."""
    return f"{camera}_{model}_frame"


def interpolate_pose(X_a: RigidTransform, X_b: RigidTransform, alpha: float) -> RigidTransform:
    """Linear in translation, slerp in rotation; ``alpha`` = 0 gives X_a, 1 gives X_b."""
    q = X_a.rotation().ToQuaternion().slerp(alpha, X_b.rotation().ToQuaternion())
    p = (1.0 - alpha) * X_a.translation() + alpha * X_b.translation()
    return RigidTransform(q, p)
