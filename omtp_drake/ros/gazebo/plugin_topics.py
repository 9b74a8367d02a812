"""The Gazebo plugin layer (:mod:`omtp_drake.gazebo`) on a ROS 1 run's graph: each
publication a topic (latched where the plugin latches it), each subscription a
subscriber, each service a service of the course's type, messages converted field for
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
from omtp_drake.ros.comm._core import PluginService, Publication, TrajectoryRequest, gazebo_plugins
from omtp_drake.ros.comm._core import gazebo_messages as neutral
from omtp_drake.ros.comm._core import plugin_conveyor as conveyor
from omtp_drake.ros.comm._core import plugin_gripper as gripper
from omtp_drake.ros.comm._core import plugin_proximity_ray as proximity_ray
from omtp_drake.ros.comm._core import trajectory_request as neutral_trajectory_request
from omtp_drake.ros.comm.image_messages import CameraInfo, Image, PointCloud2, PointField
from omtp_drake.ros.comm.interfaces import (
    ConveyorBeltControl,
    Proximity,
    VacuumGripperControl,
    VacuumGripperState,
)
from omtp_drake.ros.comm.messages import Header, JointState, Message, Time
from omtp_drake.ros.gazebo.cell_services import Service
from omtp_drake.ros.gazebo.sensor_topics import Source

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("gazebo")


def _header(stamp: float, frame_id: str) -> Message:
    return Header(stamp=Time(stamp), frame_id=frame_id)


#: Neutral message type -> the shim's type it is published as.
TYPES: dict[type, Any] = {
    neutral.JointStates: JointState,
    neutral.Image: Image,
    neutral.CameraInfo: CameraInfo,
    neutral.PointCloud: PointCloud2,
    gripper.VacuumGripperState: VacuumGripperState,
    proximity_ray.Proximity: Proximity,
}
#: Neutral request type -> the course's service type and how its request reads as the neutral one.
SERVICE_TYPES: dict[type, tuple[Any, Callable[[Any], Any]]] = {
    gripper.VacuumGripperControl: (
        VacuumGripperControl,
        lambda r: gripper.VacuumGripperControl(bool(r.enable)),
    ),
    conveyor.ConveyorBeltControl: (
        ConveyorBeltControl,
        lambda r: conveyor.ConveyorBeltControl(float(r.state.power)),
    ),
}
#: ROS 1's names of fields ROS 2 renamed (sensor_msgs/CameraInfo's matrices).
ROS1_NAMES = {"d": "D", "k": "K", "r": "R", "p": "P"}


def to_ros1(m: Any) -> Message:
    """A published message of the plugin layer as the shim's message, field for field."""
    fields = {ROS1_NAMES.get(k, k): v for k, v in neutral.message_fields(m).items()}
    if "fields" in fields:
        fields["fields"] = [
            PointField(name=n, offset=o, datatype=PointField.FLOAT32, count=1) for n, o in fields["fields"]
        ]
    ros_type = TYPES[type(m)]
    if "header" in ros_type.__slots__:
        fields["header"] = _header(m.stamp, m.frame_id)
    return ros_type(**fields)


def trajectory_request(msg: Any) -> TrajectoryRequest:
    """A ``trajectory_msgs/JointTrajectory`` of the shim as the request every plugin and
    controller reads."""
    return neutral_trajectory_request(msg, _seconds)


def _seconds(value: Any) -> float:
    return value.to_sec() if hasattr(value, "to_sec") else float(value)


class PublicationSource(Source):
    """A publication of the plugin layer as the session's source of one topic."""

    def __init__(self, publication: Publication, cell: Any):
        self.msg_class = TYPES[publication.message]
        self.latch = publication.latched
        self._poll = publication.poll
        self._cell = cell

    def poll(self) -> list[tuple[float, Any]]:
        return [(m.stamp, to_ros1(m)) for m in self._poll(self._cell.time)]


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
    session.services.update({s.name: course_service(s) for s in plugins.services})
    for line in plugins.warnings:
        _log.warning(line)


def _receiver(callback: Callable[[TrajectoryRequest], object]) -> Callable[[Any], None]:
    def receive(msg: Any) -> None:
        callback(trajectory_request(msg))

    return receive


def course_service(service: PluginService) -> Service:
    """A plugin's service as the course's service type: the request read as the plugin's,
    its reply's ``success`` answered."""
    ros_type, read = SERVICE_TYPES[service.request]

    def handle(request: Any) -> Any:
        return ros_type._response_class(success=service.handler(read(request)).success)

    return Service(service.name, ros_type, handle)
