"""The Gazebo plugin layer (:mod:`omtp_drake.gazebo`) on a ROS 1 run's graph: each
publication a topic, each subscription a subscriber, messages converted field for
field into the shim's types. Names as gazebo_ros (ROS 1) gives them; no rule here.

A topic published by two plugins (the arms' ``/joint_states`` and a model's joint state
publisher in the default namespace) gets both publishers' messages, as two ROS
publishers on one topic. The plugins the cell does not simulate are one warning line
each (logger ``gazebo``).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import Publication, gazebo_plugins
from omtp_drake.ros.comm._core import gazebo_messages as neutral
from omtp_drake.ros.comm.image_messages import CameraInfo, Image, PointCloud2, PointField
from omtp_drake.ros.comm.messages import Header, JointState, Message, Time
from omtp_drake.ros.gazebo.sensor_topics import Source

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("gazebo")


def _header(stamp: float, frame_id: str) -> Message:
    return Header(stamp=Time(stamp), frame_id=frame_id)


def joint_state(m: neutral.JointStates) -> Message:
    return JointState(
        header=_header(m.stamp, m.frame_id), name=list(m.names), position=list(m.positions),
        velocity=list(m.velocities),
    )  # fmt: skip


def image(m: neutral.Image) -> Message:
    return Image(
        header=_header(m.stamp, m.frame_id), height=m.height, width=m.width, encoding=m.encoding,
        is_bigendian=m.is_bigendian, step=m.step, data=m.data,
    )  # fmt: skip


def camera_info(m: neutral.CameraInfo) -> Message:
    return CameraInfo(
        header=_header(m.stamp, m.frame_id), height=m.height, width=m.width,
        distortion_model=m.distortion_model, D=list(m.d), K=list(m.k), R=list(m.r), P=list(m.p),
    )  # fmt: skip


def point_cloud(m: neutral.PointCloud) -> Message:
    fields = [
        PointField(name=f.name, offset=f.offset, datatype=PointField.FLOAT32, count=1) for f in m.fields
    ]
    return PointCloud2(
        header=_header(m.stamp, m.frame_id), height=m.height, width=m.width, fields=fields,
        is_bigendian=m.is_bigendian, point_step=m.point_step, row_step=m.row_step, data=m.data,
        is_dense=m.is_dense,
    )  # fmt: skip


#: Neutral message type -> (the shim's type, the conversion).
CONVERT: dict[type, tuple[Any, Callable[[Any], Message]]] = {
    neutral.JointStates: (JointState, joint_state),
    neutral.Image: (Image, image),
    neutral.CameraInfo: (CameraInfo, camera_info),
    neutral.PointCloud: (PointCloud2, point_cloud),
}


def trajectory_request(msg: Any) -> neutral.TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory`` of the shim as the plugin layer reads it."""
    points = tuple(
        neutral.TrajectoryPoint(tuple(float(q) for q in p.positions), _seconds(p.time_from_start))
        for p in msg.points
    )
    return neutral.TrajectoryRequest(
        msg.header.frame_id, _seconds(msg.header.stamp), tuple(msg.joint_names), points
    )


def _seconds(value: Any) -> float:
    return value.to_sec() if hasattr(value, "to_sec") else float(value)


class PublicationSource(Source):
    """A publication of the plugin layer as the session's source of one topic."""

    def __init__(self, publication: Publication, cell: Any):
        self.msg_class, self._convert = CONVERT[publication.message]
        self._poll = publication.poll
        self._cell = cell

    def poll(self) -> list[tuple[float, Any]]:
        return [(m.stamp, self._convert(m)) for m in self._poll(self._cell.time)]


class Publishers(Source):
    """Two publishers of one topic: each one's messages, in the order they come."""

    def __init__(self, first: Source, second: Source):
        if first.msg_class is not second.msg_class:
            raise ConfigError(
                f"two publishers of one topic with types {first.msg_class._type} and {second.msg_class._type}"
            )
        self.msg_class = first.msg_class
        self.latch = first.latch or second.latch
        self._sources = (first, second)

    def poll(self) -> list[tuple[float, Any]]:
        return sorted(self._sources[0].poll() + self._sources[1].poll(), key=lambda pair: pair[0])


def attach_plugins(session: Graph) -> None:
    """The cell's Gazebo plugins on ``session``: their topics and subscriptions."""
    plugins = gazebo_plugins(session.cell)
    for publication in plugins.publications:
        source = PublicationSource(publication, session.cell)
        existing = session.sources.get(publication.topic)
        session.sources[publication.topic] = source if existing is None else Publishers(existing, source)
    for subscription in plugins.subscriptions:
        session.subscribe(subscription.topic, _receiver(subscription.callback), (), 1)
    for line in plugins.warnings:
        _log.warning(line)


def _receiver(callback: Callable[[neutral.TrajectoryRequest], object]) -> Callable[[Any], None]:
    def receive(msg: Any) -> None:
        callback(trajectory_request(msg))

    return receive
