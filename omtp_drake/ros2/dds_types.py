"""ROS 2 messages rclpy has no wheel for (``tf2_msgs``, ``gazebo_msgs``, the course's own), written
over DDS by Cyclone DDS beside rclpy's Fast DDS: their mirrors, the writers, and Cyclone's config
(``/tf`` and Gazebo's states go this way only where their type support cannot be built:
:mod:`omtp_drake.ros2.packed_topics`).

A mirror is a Cyclone ``IdlStruct`` with ROS 2's DDS type name
(``tf2_msgs::msg::dds_::TFMessage_``) and ROS 2's fields in ROS 2's order, so its XCDR1
bytes are the bytes rclpy's type support writes (tests/test_ros2_tf.py compares every
mirror of a type rclpy also has with ``rclpy.serialization``). A Fast DDS node (rclpy,
``ros2 topic``, rviz2) sees the topic (``rt/tf`` is ``/tf``) with its ROS type and reads
the data. What makes that match, measured with Fast DDS 3.2 (rclpy 9) and Cyclone 11:

- mirrors are ``final`` and keyless (a keyed mirror never matches a ROS reader);
- the writers use XCDR1 (XCDR2 does not match Fast DDS readers);
- Cyclone ignores the XTypes type information Fast DDS sends
  (``IgnoreTypeInformation``): without it no ``sequence<struct>`` type matches, silently;
- discovery stays where rclpy's does (loopback only, unless ``--network``), in rclpy's domain.

Services cannot go this way (rmw_fastrtps pairs a reply with its request by a sample
identity the Python API cannot set), so neither can actions.
"""

# No `from __future__ import annotations`: Cyclone reads the fields' types from the annotations.
import weakref
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import MissingExtraError
from omtp_drake.ros2.audience import dds_heard

if TYPE_CHECKING:
    from omtp_drake.ros2.network import Ros2Network

try:
    import cyclonedds.idl.annotations as annotate
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.types import float64, int32, sequence, uint32
except ImportError as e:  # the ros2 extra's cyclonedds wheel
    raise MissingExtraError(
        f'/tf needs the cyclonedds wheel ({e}); install the project\'s ros2 extra: pip install -e ".[ros2]"'
    ) from None

_MSG = "::msg::dds_::"


@annotate.final
@dataclass
class Time_(IdlStruct, typename=f"builtin_interfaces{_MSG}Time_"):  # type: ignore[call-arg]
    sec: int32 = 0
    nanosec: uint32 = 0


@annotate.final
@dataclass
class Header_(IdlStruct, typename=f"std_msgs{_MSG}Header_"):  # type: ignore[call-arg]
    stamp: Time_ = field(default_factory=Time_)
    frame_id: str = ""


@annotate.final
@dataclass
class Vector3_(IdlStruct, typename=f"geometry_msgs{_MSG}Vector3_"):  # type: ignore[call-arg]
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@annotate.final
@dataclass
class Point_(IdlStruct, typename=f"geometry_msgs{_MSG}Point_"):  # type: ignore[call-arg]
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@annotate.final
@dataclass
class Quaternion_(IdlStruct, typename=f"geometry_msgs{_MSG}Quaternion_"):  # type: ignore[call-arg]
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0
    w: float64 = 1.0


@annotate.final
@dataclass
class Transform_(IdlStruct, typename=f"geometry_msgs{_MSG}Transform_"):  # type: ignore[call-arg]
    translation: Vector3_ = field(default_factory=Vector3_)
    rotation: Quaternion_ = field(default_factory=Quaternion_)


@annotate.final
@dataclass
class TransformStamped_(IdlStruct, typename=f"geometry_msgs{_MSG}TransformStamped_"):  # type: ignore[call-arg]
    header: Header_ = field(default_factory=Header_)
    child_frame_id: str = ""
    transform: Transform_ = field(default_factory=Transform_)


@annotate.final
@dataclass
class Pose_(IdlStruct, typename=f"geometry_msgs{_MSG}Pose_"):  # type: ignore[call-arg]
    position: Point_ = field(default_factory=Point_)
    orientation: Quaternion_ = field(default_factory=Quaternion_)


@annotate.final
@dataclass
class Twist_(IdlStruct, typename=f"geometry_msgs{_MSG}Twist_"):  # type: ignore[call-arg]
    linear: Vector3_ = field(default_factory=Vector3_)
    angular: Vector3_ = field(default_factory=Vector3_)


@annotate.final
@dataclass
class TFMessage_(IdlStruct, typename=f"tf2_msgs{_MSG}TFMessage_"):  # type: ignore[call-arg]
    transforms: sequence[TransformStamped_] = field(default_factory=list)


@annotate.final
@dataclass
class ModelStates_(IdlStruct, typename=f"gazebo_msgs{_MSG}ModelStates_"):  # type: ignore[call-arg]
    name: sequence[str] = field(default_factory=list)
    pose: sequence[Pose_] = field(default_factory=list)
    twist: sequence[Twist_] = field(default_factory=list)


@annotate.final
@dataclass
class LinkStates_(IdlStruct, typename=f"gazebo_msgs{_MSG}LinkStates_"):  # type: ignore[call-arg]
    name: sequence[str] = field(default_factory=list)
    pose: sequence[Pose_] = field(default_factory=list)
    twist: sequence[Twist_] = field(default_factory=list)


#: Mirror -> its ROS 2 type (``pkg/msg/Name``): what a bag's schema and ``ros2 topic`` call it.
ROS_TYPES: dict[type, str] = {
    cls: cls.__idl_typename__.replace("::msg::dds_::", "/msg/").removesuffix("_")
    for cls in (
        Time_,
        Header_,
        Vector3_,
        Point_,
        Quaternion_,
        Transform_,
        TransformStamped_,
        Pose_,
        Twist_,
        TFMessage_,
        ModelStates_,
        LinkStates_,
    )
}


def cyclone_config(network: "Ros2Network") -> str:
    """Cyclone's XML config for ``network``: the one place it is written (see the module doc)."""
    where = (
        ""
        if network.subnet
        else '<General><Interfaces><NetworkInterface name="lo"/></Interfaces>'
        "<AllowMulticast>false</AllowMulticast></General>"
        '<Discovery><Peers><Peer address="127.0.0.1"/></Peers>'
        "<ParticipantIndex>auto</ParticipantIndex></Discovery>"
    )
    return (
        '<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">'
        f"{where}<Compatibility><IgnoreTypeInformation>1.15</IgnoreTypeInformation></Compatibility>"
        "</Domain></CycloneDDS>"
    )


#: The Cyclone domains this process has configured, by id (Cyclone configures a domain once per
#: process; the participants on it share it, and it goes when the last of them does).
_DOMAINS: "weakref.WeakValueDictionary[int, Any]" = weakref.WeakValueDictionary()


class CycloneParticipant:
    """A Cyclone DDS participant on ``network``, and the ROS 2 topics it writes."""

    def __init__(self, network: "Ros2Network"):
        from cyclonedds.domain import Domain, DomainParticipant

        domain = _DOMAINS.get(network.domain_id)
        if domain is None:
            domain = _DOMAINS[network.domain_id] = Domain(network.domain_id, cyclone_config(network))
        self._domain = domain
        self.participant = DomainParticipant(network.domain_id)

    def writer(self, topic: str, mirror: type, *, latched: bool = False, depth: int = 100) -> Any:
        """A writer of ``mirror`` on the ROS 2 topic ``topic`` (``/tf``), reliable; ``latched``:
        transient local, as ``/tf_static`` (the last ``depth`` samples kept for late readers)."""
        from cyclonedds.core import Policy, Qos
        from cyclonedds.pub import DataWriter
        from cyclonedds.topic import Topic
        from cyclonedds.util import duration

        durability = Policy.Durability.TransientLocal if latched else Policy.Durability.Volatile
        qos = Qos(
            Policy.Reliability.Reliable(duration(seconds=1)),
            durability,
            Policy.History.KeepLast(depth),
            Policy.DataRepresentation(use_cdrv0_representation=True),
        )
        return DataWriter(self.participant, Topic(self.participant, "rt" + topic, mirror), qos=qos)


def write_cdr(writer: Any, data: bytes) -> None:
    """Writes ``data``, the XCDR1 bytes of a sample of ``writer``'s type (packed by
    :mod:`omtp_drake.ros2.cdr`), as ``writer.write(sample)`` writes the sample's serialization
    (the same C call, without Cyclone's Python serializer)."""
    from cyclonedds._clayer import ddspy_write
    from cyclonedds.core import DDSException

    ret = ddspy_write(writer._ref, data)
    if ret < 0:
        raise DDSException(ret, f"Occurred while writing a sample of {writer.topic.name}")


class CdrTopic:
    """A ROS 2 topic written as packed XCDR1 bytes (:mod:`omtp_drake.ros2.cdr`) by a writer of
    ``dds``; with ``bag`` (``--bag``), each message goes into the bag too, its type's definition
    added once."""

    def __init__(
        self, dds: CycloneParticipant, topic: str, mirror: type, bag: Any = None, **qos: Any
    ) -> None:
        self.topic, self.type_name = topic, ROS_TYPES[mirror]
        # The participant lives while a topic of it does (Cyclone deletes its children with it).
        self._dds: Any = dds
        self._writer = dds.writer(topic, mirror, **qos)
        self._bag = bag
        if bag is not None:
            from omtp_drake.ros.bag.definitions import concatenated, installed_text

            bag.add_type(self.type_name, concatenated(self.type_name, installed_text))

    def wanted(self) -> bool:
        """Whether a message would reach anyone: a matched reader, or the bag (``audience``)."""
        return self._writer is not None and dds_heard(self._writer, self._bag)

    def write(self, data: bytes, now: float, stamp: "float | None" = None) -> None:
        """Writes ``data`` at simulated time ``now`` (``stamp``: the message's own, for the bag)."""
        if self._writer is None:
            return
        write_cdr(self._writer, data)
        if self._bag is not None:
            self._bag.write_cdr(self.topic, self.type_name, data, now, stamp)

    def close(self) -> None:
        """Drops the writer: Cyclone deletes it (and, with its last topic, the participant)."""
        self._writer = self._dds = None
