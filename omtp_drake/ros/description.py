"""``/robot_description`` and ``/robot_description_semantic`` of the cell, as parameters.

The semantic description is the course's MoveIt config in SRDF form: robot
``omtp``, a group per arm (chain from ``robotN_base_link`` to
``vacuum_gripperN_suction_cup``) and a ``group_state`` per named pose of the
cell (``R1Home``...), with the values the cell's planner uses; a student's own
SRDF (their named states) replaces it with ``--srdf FILE``. The robot
description lists the arms' revolute joints with their limits, read from the
cell's plant (states that parse it look up joint names and limits).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from omtp_drake.errors import ConfigError
from omtp_drake.ros._core import tool_frame_names
from omtp_drake.ros.trajectories import joint_names

if TYPE_CHECKING:
    from omtp_drake.script import Cell


def semantic_description(cell: Cell) -> str:
    """The cell's SRDF (see the module doc)."""
    from omtp_drake.cell.arms import NAMED_POSES

    robot = ET.Element("robot", name="omtp")
    for name in cell.station.arms:
        tip = tool_frame_names(cell.arm(name).config)["suction_cup"]
        group = ET.SubElement(robot, "group", name=name)
        ET.SubElement(group, "chain", base_link=f"{name}_base_link", tip_link=tip)
    for name in cell.station.arms:
        prefix = cell.arm(name).config.pose_prefix
        for pose, values in NAMED_POSES.items():
            if pose.startswith(prefix):
                state = ET.SubElement(robot, "group_state", name=pose, group=name)
                for joint, value in zip(joint_names(name), values):
                    ET.SubElement(state, "joint", name=joint, value=f"{value:g}")
    ET.indent(robot)
    return '<?xml version="1.0" ?>\n' + ET.tostring(robot, encoding="unicode")


def robot_description(cell: Cell) -> str:
    """The arms' joints with their limits, in URDF (see the module doc)."""
    plant = cell.station.plant
    robot = ET.Element("robot", name="omtp")
    for arm in cell.station.arms:
        for name in joint_names(arm):
            joint = plant.GetJointByName(name)
            for link in (joint.parent_body().name(), joint.child_body().name()):
                if robot.find(f"link[@name='{link}']") is None:
                    ET.SubElement(robot, "link", name=link)
            element = ET.SubElement(robot, "joint", name=name, type="revolute")
            ET.SubElement(element, "parent", link=joint.parent_body().name())
            ET.SubElement(element, "child", link=joint.child_body().name())
            ET.SubElement(
                element,
                "limit",
                lower=f"{joint.position_lower_limits()[0]:g}",
                upper=f"{joint.position_upper_limits()[0]:g}",
                velocity=f"{joint.velocity_upper_limits()[0]:g}",
                effort="0",
            )
    ET.indent(robot)
    return '<?xml version="1.0" ?>\n' + ET.tostring(robot, encoding="unicode")


def load_srdf(path: Optional[str | Path]) -> Optional[str]:
    """The text of an SRDF file (checked to be XML with a ``<robot>`` root)."""
    if path is None:
        return None
    file = Path(path)
    if not file.is_file():
        raise ConfigError(f"--srdf {str(path)!r} does not exist")
    text = file.read_text()
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise ConfigError(f"--srdf {path}: not valid XML: {e}") from None
    if root.tag != "robot":
        raise ConfigError(f"--srdf {path}: the root element is <{root.tag}>, not <robot>")
    return text
