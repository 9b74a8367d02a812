"""The plugins' topics whose type is the course's own (``omtp_gazebo/VacuumGripperState``,
``omtp_gazebo/Proximity``), over ROS 2: each on its ROS 1 name in the course's type, written
by Cyclone DDS (:mod:`omtp_drake.ros2.course_types`), and ``std_msgs/Bool`` views of its
flags for a plain rclpy node, through rclpy.

=================================  ==================================  =====================================
topic                              type                                what
=================================  ==================================  =====================================
``/gripperN/state``                ``omtp_gazebo/VacuumGripperState``  the plugin's message (Cyclone)
``/gripperN/enabled``, ``attached``  ``std_msgs/Bool``                  its ``enabled``, ``attached``
``/break_beam_sensor``,            ``omtp_gazebo/Proximity``           the plugin's messages (Cyclone)
``/break_beam_sensor_change``
``<that topic>/object_detected``   ``std_msgs/Bool``                   their ``object_detected``
=================================  ==================================  =====================================

When, and what the messages say, is the plugin layer's (:mod:`omtp_drake.gazebo.vacuum_gripper`,
:mod:`omtp_drake.gazebo.proximity_ray`); a latched topic is transient local (depth 1) here,
its view too, so a late reader gets the last message. A topic that is not latched, and each of
its views, goes out only while someone would get it (:mod:`omtp_drake.ros2.audience`: the
gripper's state is due at every step). Cyclone DDS (its import, its participant) is asked for
only when a topic of these types is made: a cell without them (a robot of the user's own) runs
without it.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.gazebo.proximity_ray import Proximity
from omtp_drake.gazebo.schedule import Publication
from omtp_drake.gazebo.vacuum_gripper import VacuumGripperState
from omtp_drake.ros2 import cdr
from omtp_drake.ros2.audience import dds_heard, heard

if TYPE_CHECKING:
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.course_types import Proximity_, VacuumGripperState_
    from omtp_drake.ros2.dds_types import CycloneParticipant, Time_


def _time(t: float) -> Time_:
    from omtp_drake.ros2.dds_types import Time_

    ns = int(round(t * 1e9))
    return Time_(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def _gripper_state(m: VacuumGripperState) -> VacuumGripperState_:
    from omtp_drake.ros2.course_types import VacuumGripperState_

    return VacuumGripperState_(enabled=m.enabled, attached=m.attached)


def _pack_gripper_state(m: VacuumGripperState) -> bytes:
    """The XCDR1 bytes of :func:`_gripper_state`'s sample (two bools after the header), packed
    at once: it goes out at every step, where Cyclone's Python serializer cost 1 ms a message."""
    return cdr.HEADER + bytes((m.enabled, m.attached))


def _proximity(m: Proximity) -> Proximity_:
    from omtp_drake.ros2.course_types import Proximity_
    from omtp_drake.ros2.dds_types import Header_

    return Proximity_(
        header=Header_(stamp=_time(m.stamp), frame_id=m.frame_id),
        object_detected=m.object_detected,
        min_range=m.min_range,
        max_range=m.max_range,
    )


def _beside(topic: str, name: str) -> str:
    """``/gripper1/state`` -> ``/gripper1/<name>``."""
    return topic.rsplit("/", 1)[0] + "/" + name


def _below(topic: str, name: str) -> str:
    """``/break_beam_sensor`` -> ``/break_beam_sensor/<name>``."""
    return topic + "/" + name


@dataclass(frozen=True)
class CourseType:
    """How a plugin message goes out: its mirror (by its name in
    :mod:`~omtp_drake.ros2.course_types`), the conversion to a mirror's sample, its Bool views'
    fields and where their topics go (beside or below the message's topic), and ``pack``, its
    XCDR1 bytes at once (None: the sample's, as Cyclone serializes it)."""

    mirror_name: str
    convert: Callable[[Any], Any]
    view_fields: tuple[str, ...]
    view_topic: Callable[[str, str], str]
    pack: Optional[Callable[[Any], bytes]] = None

    @property
    def mirror(self) -> type:
        """The mirror (imported here: Cyclone DDS comes with it)."""
        return getattr(importlib.import_module("omtp_drake.ros2.course_types"), self.mirror_name)

    def data(self, message: Any) -> bytes:
        """``message``'s XCDR1 bytes (with their encapsulation header)."""
        if self.pack is not None:
            return self.pack(message)
        return self.convert(message).serialize(use_version_2=False)


#: The plugin layer's messages of the course's types -> how they go out.
COURSE_TYPES: dict[type, CourseType] = {
    VacuumGripperState: CourseType(
        "VacuumGripperState_", _gripper_state, ("enabled", "attached"), _beside, _pack_gripper_state
    ),
    Proximity: CourseType("Proximity_", _proximity, ("object_detected",), _below),
}


class CourseTopic:
    """One publication of a course type: the Cyclone writer and the rclpy Bool view."""

    def __init__(self, node: Any, dds: CycloneParticipant, publication: Publication, bag: Optional[Ros2Bag]):
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from std_msgs.msg import Bool

        from omtp_drake.ros2.course_types import ros_type
        from omtp_drake.ros2.dds_types import write_cdr

        self._write_cdr = write_cdr
        self._kind = COURSE_TYPES[publication.message]
        self._topic = publication.topic
        self._poll = publication.poll
        self._bag = bag
        self._type_name = ros_type(self._kind.mirror)
        if bag is not None:
            from omtp_drake.ros.bag.definitions import concatenated
            from omtp_drake.ros.bag.ros1 import ros2_text
            from omtp_drake.ros.comm import interfaces  # noqa: F401  (declares the course's types' text)

            bag.add_type(self._type_name, concatenated(self._type_name, ros2_text))
        latched = publication.latched
        self._writer = dds.writer(
            publication.topic, self._kind.mirror, latched=latched, depth=1 if latched else 10
        )
        qos: Any = (
            QoSProfile(
                depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
            )
            if latched
            else 10
        )
        self._views = {
            name: node.create_publisher(Bool, self._kind.view_topic(publication.topic, name), qos)
            for name in self._kind.view_fields
        }
        self._bool = Bool
        self._latched = latched

    def __call__(self, t: float) -> None:
        for message in self._poll(t):
            if self._latched or dds_heard(self._writer, self._bag):
                data = self._kind.data(message)
                self._write_cdr(self._writer, data)
                if self._bag is not None:
                    stamp = getattr(message, "stamp", None)
                    self._bag.write_cdr(self._topic, self._type_name, data, t, stamp)
            for name, view in self._views.items():
                if self._latched or heard(view):
                    view.publish(self._bool(data=bool(getattr(message, name))))


class CourseTopics:
    """The topics above for ``publications`` (those of a course type) on ``node``, their writers on
    the Cyclone DDS participant ``dds()`` gives (asked for only if there is one)."""

    def __init__(
        self,
        node: Any,
        dds: Callable[[], CycloneParticipant],
        publications: list[Publication],
        bag: Optional[Ros2Bag] = None,
    ):
        self._topics = [CourseTopic(node, dds(), p, bag) for p in publications if p.message in COURSE_TYPES]

    def __call__(self, t: float) -> None:
        for topic in self._topics:
            topic(t)

    def close(self) -> None:
        """Leaves the DDS graph (Cyclone deletes the writers and participant with their last reference)."""
        self._topics = []
