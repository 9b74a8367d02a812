"""ROS 1 tf's ``TransformListener`` (``tf.TransformListener``, ``tf.listener``) on the
cell's tf2 buffer: ``waitForTransform``, ``canTransform``, ``lookupTransform``
(``(translation, quaternion xyzw)``), ``transformPose``, ``frameExists``. FlexBE's
``ProxyTransformListener`` and moveit_python's ``MoveGroupInterface`` hand one out.
The cell records its frames itself: the listener subscribes to nothing.
"""

from __future__ import annotations

from typing import Any

from omtp_drake.ros.comm.session import current
from omtp_drake.ros.tf.tf2 import Buffer, TimeoutException


class TransformListener:
    """ROS 1 tf's ``tf.TransformListener`` on the cell's tf2 buffer (see the module doc)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.buffer = Buffer()

    def waitForTransform(self, target: str, source: str, time: Any, timeout: Any) -> None:  # noqa: N802
        if not self.buffer.can_transform(target, source, time, timeout):
            raise TimeoutException(f"no transform from {source} to {target} within the timeout")

    def canTransform(self, target: str, source: str, time: Any) -> bool:  # noqa: N802
        return bool(self.buffer.can_transform(target, source, time))

    def lookupTransform(self, target: str, source: str, time: Any) -> tuple[list[float], list[float]]:  # noqa: N802
        t = self.buffer.lookup_transform(target, source, time).transform
        return [t.translation.x, t.translation.y, t.translation.z], [
            t.rotation.x,
            t.rotation.y,
            t.rotation.z,
            t.rotation.w,
        ]

    def transformPose(self, target: str, pose: Any) -> Any:  # noqa: N802
        return self.buffer.transform(pose, target)

    def frameExists(self, frame: str) -> bool:  # noqa: N802
        return frame.lstrip("/") in current().cell.tf.all_frame_names()
