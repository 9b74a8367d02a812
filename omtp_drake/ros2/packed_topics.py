"""The node's topics of types no PyPI wheel has (``tf2_msgs/TFMessage``, ``gazebo_msgs/ModelStates``
and ``LinkStates``), their messages packed once as CDR bytes (:mod:`omtp_drake.ros2.cdr`) and
written by one of two routes, chosen once per node (:class:`PackedTopics`):

- **rclpy**, with the type support built here (:mod:`omtp_drake.ros2.interface_build`), whenever
  it can be built (a C/C++ compiler; once, into the model cache): publishers of the node
  ``/omtp_cell`` like its other topics, of the real types, taking the packed bytes as rclpy takes
  a serialized message (``Publisher.publish(bytes)``);
- **Cyclone DDS** writers of the mirrors (:mod:`omtp_drake.ros2.dds_types`) beside rclpy, on a
  machine where it cannot be built: one warning says so, and why.

Either way a reader sees the ROS type and reads the same bytes (tests compare them with
``rclpy.serialization``). A volatile topic's message is packed only while someone would receive
it (:func:`omtp_drake.ros2.audience.heard`); a latched one goes out regardless.
"""

from __future__ import annotations

import importlib
import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Optional, Protocol

from omtp_drake.ros2 import interface_build
from omtp_drake.ros2.audience import heard

if TYPE_CHECKING:
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.dds_types import CycloneParticipant

_log = logging.getLogger("gazebo")

#: Said once where tf2_msgs and gazebo_msgs cannot be built (followed by why).
BY_CYCLONE = (
    "/tf, /tf_static, /gazebo/model_states and /gazebo/link_states are written by Cyclone DDS "
    "beside rclpy (a reader with the types reads them; the graph lists no node publishing them): "
    "tf2_msgs and gazebo_msgs have no PyPI package and their type support could not be built here"
)


class PackedTopic(Protocol):
    """One topic written as packed CDR bytes, by either route."""

    topic: str
    type_name: str

    def wanted(self) -> bool:
        """Whether a message would reach anyone now (see the module doc)."""

    def write(self, data: bytes, now: float, stamp: Optional[float] = None) -> None:
        """Writes ``data`` at simulated time ``now`` (``stamp``: the message's own, for a bag)."""

    def close(self) -> None:
        """Leaves the graph."""


class RclpyPackedTopic:
    """A topic of ``node``, an rclpy publisher of the built type ``type_name`` (``pkg/msg/Name``),
    reliable, transient local if ``latched``, KEEP_LAST ``depth``. A ``--bag`` records it as the
    node's other publishers (:func:`omtp_drake.ros2.bag.record_publishers`)."""

    def __init__(self, node: Any, topic: str, type_name: str, *, latched: bool = False, depth: int = 100):
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

        package, _, name = type_name.split("/")
        msg_type = getattr(importlib.import_module(f"{package}.msg"), name)
        durability = DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE
        qos = QoSProfile(depth=depth, durability=durability, reliability=ReliabilityPolicy.RELIABLE)
        self.topic, self.type_name = topic, type_name
        self._publisher = node.create_publisher(msg_type, topic, qos)

    def wanted(self) -> bool:
        return heard(self._publisher)

    def write(self, data: bytes, now: float, stamp: Optional[float] = None) -> None:
        self._publisher.publish(data)

    def close(self) -> None:
        """Nothing of its own: the node destroys its publishers."""


class PackedTopics:
    """The route of a node's packed topics: rclpy on ``node`` if ``tf2_msgs`` and ``gazebo_msgs``
    can be built here (the one rule, :func:`~omtp_drake.ros2.interface_build.activated`), else
    Cyclone DDS on the participant ``dds()`` gives (asked for only on that route: rclpy's needs no
    Cyclone at all) with one warning; ``bag``: the run's (``--bag``)."""

    def __init__(self, node: Any, dds: Callable[[], CycloneParticipant], bag: Optional[Ros2Bag] = None):
        self._node, self._dds, self._bag = node, dds, bag
        #: ``"rclpy"`` or ``"cyclone"``: who writes the topics.
        self.route = "rclpy" if interface_build.activated(BY_CYCLONE, _log.warning) else "cyclone"

    def topic(self, topic: str, type_name: str, *, latched: bool = False, depth: int = 100) -> PackedTopic:
        """The topic ``topic`` of the ROS type ``type_name`` (``pkg/msg/Name``, one of a mirror's
        :data:`~omtp_drake.ros2.dds_types.ROS_TYPES`)."""
        if self.route == "rclpy":
            return RclpyPackedTopic(self._node, topic, type_name, latched=latched, depth=depth)
        from omtp_drake.ros2.dds_types import ROS_TYPES, CdrTopic

        (mirror,) = [m for m, name in ROS_TYPES.items() if name == type_name]
        return CdrTopic(self._dds(), topic, mirror, self._bag, latched=latched, depth=depth)
