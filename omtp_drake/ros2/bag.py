"""``omtp-drake ros2 --bag run.mcap``: every message the cell's node publishes, into a ROS 2
bag (:class:`~omtp_drake.ros.bag.writer.Ros2Bag`), with its simulated stamps.

rclpy's messages go in as rclpy serializes them (the bytes a ``ros2 bag record`` would
store) under their installed ``.msg`` definitions (or those of the packages built here); the
topics Cyclone DDS writes where those cannot be built (``/tf``...) are bagged by their
writers (:class:`~omtp_drake.ros2.dds_types.CdrTopic`). Latched topics
(``/robot_description``) carry their transient-local QoS in the channel's metadata, so
``ros2 bag play`` offers them latched again.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from omtp_drake.ros.bag.definitions import concatenated, installed_text, ros2_name
from omtp_drake.ros.bag.writer import Ros2Bag
from omtp_drake.ros2.interface_build import DEFINITIONS

#: rosbag2's offered QoS of a reliable, transient-local publisher of depth 1 (a latched topic).
LATCHED_QOS = (
    "- history: 1\n  depth: 1\n  reliability: 1\n  durability: 1\n"
    "  deadline:\n    sec: 0\n    nsec: 0\n  lifespan:\n    sec: 0\n    nsec: 0\n"
    "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 0\n    nsec: 0\n"
    "  avoid_ros_namespace_conventions: false\n"
)


def ros_type(msg_type: type) -> str:
    """``pkg/msg/Name`` of an rclpy message class."""
    return f"{msg_type.__module__.split('.')[0]}/msg/{msg_type.__name__}"


class _RecordedPublisher:
    """An rclpy publisher whose messages also go into the bag (anything else is the publisher's);
    a message given as its serialized bytes (:mod:`omtp_drake.ros2.packed_topics`) goes in as is."""

    #: Its messages reach the bag (:func:`omtp_drake.ros2.audience.heard`).
    recorded = True

    def __init__(self, publisher: Any, type_name: str, bag: Ros2Bag, clock: Callable[[], float], qos: str):
        from rclpy.serialization import serialize_message

        self._publisher = publisher
        self._type = type_name
        self._bag = bag
        self._clock = clock
        self._qos = qos
        self._serialize = serialize_message

    def publish(self, msg: Any) -> None:
        self._publisher.publish(msg)
        header = getattr(msg, "header", None)
        stamp = None if header is None else header.stamp.sec + header.stamp.nanosec * 1e-9
        data = msg if isinstance(msg, bytes) else self._serialize(msg)
        self._bag.write_cdr(self._publisher.topic_name, self._type, data, self._clock(), stamp, self._qos)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._publisher, name)


def message_text(type_name: str) -> str | None:
    """The ``.msg`` text of ``type_name``: an installed wheel's, else one of the packages built
    here (:mod:`omtp_drake.ros2.interface_build`, ``control_msgs``...)."""
    text = installed_text(type_name)
    if text is None:
        package, _, short = ros2_name(type_name).split("/")
        path = DEFINITIONS / package / "msg" / f"{short}.msg"
        text = path.read_text() if path.is_file() else None
    return text


def record_publishers(node: Any, bag: Ros2Bag, clock: Callable[[], float]) -> None:
    """From now on each publisher ``node`` creates also writes into ``bag``, at ``clock()``'s time."""
    from rclpy.qos import DurabilityPolicy

    create = node.create_publisher

    def create_recorded(msg_type: Any, topic: str, qos: Any, **kwargs: Any) -> Any:
        publisher = create(msg_type, topic, qos, **kwargs)
        name = ros_type(msg_type)
        bag.add_type(name, concatenated(name, message_text))
        latched = publisher.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
        return _RecordedPublisher(publisher, name, bag, clock, LATCHED_QOS if latched else "")

    node.create_publisher = create_recorded
