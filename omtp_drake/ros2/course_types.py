"""The course's ``omtp_gazebo`` messages the plugins publish, as Cyclone DDS mirrors: no
package of them exists for ROS 2 (nor on PyPI), so Cyclone writes them beside rclpy, in
ROS 2's DDS type names (``omtp_gazebo::msg::dds_::Proximity_``), final, keyless, XCDR1,
as :mod:`omtp_drake.ros2.dds_types` says why. A ROS 2 node that has the type (a port of
``omtp_gazebo`` built by the user, or a raw DDS reader of these mirrors) reads them; a plain
rclpy node reads their ``std_msgs`` views (:mod:`omtp_drake.ros2.course_topics`).
"""

# No `from __future__ import annotations`: Cyclone reads the fields' types from the annotations.
from dataclasses import dataclass, field

import cyclonedds.idl.annotations as annotate
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import float32

from omtp_drake.ros2.dds_types import Header_

_MSG = "omtp_gazebo::msg::dds_::"


@annotate.final
@dataclass
class VacuumGripperState_(IdlStruct, typename=f"{_MSG}VacuumGripperState_"):  # type: ignore[call-arg]
    enabled: bool = False
    attached: bool = False


@annotate.final
@dataclass
class Proximity_(IdlStruct, typename=f"{_MSG}Proximity_"):  # type: ignore[call-arg]
    header: Header_ = field(default_factory=Header_)
    object_detected: bool = False
    min_range: float32 = 0.0
    max_range: float32 = 0.0


def ros_type(mirror: type) -> str:
    """``omtp_gazebo/msg/Name`` of a mirror (what ``ros2 topic list -t`` and a bag call it)."""
    return mirror.__idl_typename__.replace("::msg::dds_::", "/msg/").removesuffix("_")  # type: ignore[attr-defined]
