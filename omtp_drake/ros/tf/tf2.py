"""tf2_ros and tf2_geometry_msgs on the cell's tf buffer (``cell.tf``).

``Buffer.lookup_transform(target, source, time, timeout)`` returns a
``geometry_msgs/TransformStamped``: the pose of ``source`` in ``target`` (tf2's
meaning). ``rospy.Time(0)`` asks for the latest transform. With a ``timeout``
a lookup that cannot be answered yet (a frame a camera has not seen yet, a time
not reached yet) waits, advancing simulated time, as tf2's does. Errors have
tf2's classes: LookupException (unknown frame), ExtrapolationException (a time
outside the buffer's history).
"""

from __future__ import annotations

import copy
from typing import Any, Optional

from omtp_drake.errors import FrameError, UnknownNameError
from omtp_drake.ros.comm._core import single_camera
from omtp_drake.ros.comm.messages import Header, Message, PoseStamped, Time, TransformStamped
from omtp_drake.ros.comm.rostime import _blocking
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.gazebo.sensor_topics import SINGLE_CAMERA_FRAME
from omtp_drake.ros.tf.convert import pose_msg, rigid, transform_msg


class TransformException(Exception):
    pass


class LookupException(TransformException):
    pass


class ConnectivityException(TransformException):
    pass


class ExtrapolationException(TransformException):
    pass


class InvalidArgumentException(TransformException):
    pass


class TimeoutException(TransformException):
    pass


def _frame(name: str) -> str:
    """A frame name as the cell's buffer knows it (no leading slash). The lecture's
    single camera's frames are its camera's: ``logical_camera_frame`` and, for a frame
    the buffer does not have, ``logical_camera_<model>_frame`` (the plugin's frame of a
    model that camera lists)."""
    name = str(name).lstrip("/")
    prefix = SINGLE_CAMERA_FRAME.removesuffix("frame")
    if not name.startswith(prefix) or not name.endswith("_frame"):
        return name
    cell = current().cell
    camera = single_camera(cell)
    if camera is None:
        return name
    if name == SINGLE_CAMERA_FRAME:
        return f"{camera}_frame"
    frames = cell.tf.all_frame_names()
    mapped = f"{camera}_{name.removeprefix(prefix)}"
    return mapped if name not in frames and mapped in frames else name


def _seconds(time: Any) -> Optional[float]:
    """None (latest) for Time(0) or None; else the stamp's seconds."""
    if time is None:
        return None
    seconds = time.to_sec() if hasattr(time, "to_sec") else float(time)
    return None if seconds == 0 else seconds


class Buffer:
    """tf2_ros.Buffer over the cell's frames (the cell records them every tick)."""

    def __init__(self, cache_time: Any = None, debug: bool = False):
        self._session = current()

    def _lookup(self, target: str, source: str, time: Any) -> Any:
        cell = self._session.cell
        t = _seconds(time)
        if t is not None and cell.tf.times and cell.tf.times[-1] < t <= cell.time + 1e-9:
            cell.tf.record(cell.runtime.context)  # the state now, for a stamp of now
        try:
            return cell.tf.lookup_transform(_frame(target), _frame(source), t)
        except UnknownNameError as e:
            raise LookupException(str(e)) from None
        except FrameError as e:
            raise ExtrapolationException(str(e)) from None

    def _wait(self, target: str, source: str, time: Any, timeout: Any) -> None:
        """Advances up to ``timeout`` until the transform can be looked up."""
        seconds = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
        if seconds <= 0 or self.can_transform(target, source, time):
            return
        session = self._session
        with _blocking():
            session.run_until(session.time + seconds, until=lambda: self.can_transform(target, source, time))

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = None
    ) -> Message:
        self._wait(target_frame, source_frame, time, timeout)
        stamped = self._lookup(target_frame, source_frame, time)
        header = Header(stamp=Time(stamped.time), frame_id=str(target_frame).lstrip("/"))
        return TransformStamped(
            header=header,
            child_frame_id=str(source_frame).lstrip("/"),
            transform=transform_msg(stamped.transform),
        )

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Any,
        timeout: Any = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        if timeout is not None and not (hasattr(timeout, "to_sec") and timeout.to_sec() == 0):
            self._wait(target_frame, source_frame, time, timeout)
        try:
            self._lookup(target_frame, source_frame, time)
            ok, why = True, ""
        except TransformException as e:
            ok, why = False, str(e)
        return (ok, why) if return_debug_tuple else ok

    def transform(
        self, object_stamped: Any, target_frame: str, timeout: Any = None, new_type: Any = None
    ) -> Any:
        """A PoseStamped expressed in ``target_frame`` at its stamp (tf2's Buffer.transform)."""
        if new_type is not None and new_type is not PoseStamped:
            raise InvalidArgumentException(f"transform to {new_type} is not supported; only PoseStamped")
        if not isinstance(object_stamped, PoseStamped):
            raise TypeError(
                f"Buffer.transform takes a geometry_msgs PoseStamped, got {type(object_stamped).__name__}"
            )
        header = object_stamped.header
        transform = self.lookup_transform(target_frame, header.frame_id, header.stamp, timeout)
        return do_transform_pose(object_stamped, transform)

    def all_frames_as_string(self) -> str:
        return "\n".join(f"Frame {name} exists" for name in self._session.cell.tf.all_frame_names())


class TransformListener:
    """tf2_ros.TransformListener: the cell records the frames itself; this only holds the buffer."""

    def __init__(
        self, buffer: Buffer, queue_size: Any = None, buff_size: Any = None, tcp_nodelay: bool = False
    ):
        if not isinstance(buffer, Buffer):
            raise TypeError(f"TransformListener needs a tf2_ros.Buffer, got {type(buffer).__name__}")
        self.buffer = buffer

    def unregister(self) -> None:
        pass


def do_transform_pose(pose: Message, transform: Message) -> Message:
    """tf2_geometry_msgs.do_transform_pose: ``transform`` applied to ``pose`` (X_TS @ X_SP)."""
    X_TP = rigid(transform.transform, "transform") @ rigid(pose.pose, "pose")
    return PoseStamped(header=copy.deepcopy(transform.header), pose=pose_msg(X_TP))
