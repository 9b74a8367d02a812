"""``/robot_description``: the cell's URDF text, as the course's launch files load it.

The course loads one URDF of the whole cell (its ``omtp_factory.xacro``). The
cell here is built from several models (:func:`~omtp_drake.cell.station.add_cell_models`:
floor, pedestals, arms and grippers, bins, conveyor, break beam, deletion wall,
camera frames) welded into the world, and the URDF models spawned into it (a robot file,
a launch file's ``spawn_model``). :func:`robot_description` merges the same
models' URDFs (the xacro sources expanded, the converted UR arms) into one
``<robot name="omtp">`` with a ``world`` link, and writes each weld the plant
made as a fixed joint from its parent link, at the pose it has in the running
cell. Parts are no part of it (they are Gazebo models in the course too).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING

from pydrake.math import RollPitchYaw

from omtp_drake.ros.comm._core import MODELS_DIR, arm_urdf, expand_xacro, gripper_urdf

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

_DRAKE_NS = "http://drake.mit.edu"


def _model_texts(cell: Cell) -> list[str]:
    """The URDF texts of the models the cell is built from (not its parts)."""
    scenario = cell.runtime.station.scenario
    texts = [expand_xacro(MODELS_DIR / "floor.urdf.xacro")]
    for robot in scenario.robots:
        if not robot.pedestal_model:  # (the student's own is one of the models below)
            texts.append(
                expand_xacro(
                    MODELS_DIR / "pedestal.urdf.xacro",
                    {"name": f"{robot.name}_pedestal", "height": robot.pedestal_height},
                )
            )
        texts.append(arm_urdf(robot).read_text())
        if robot.gripper:
            texts.append(gripper_urdf(robot))
    # (a bin of the student's own is one of the models below, as their file writes it)
    texts += [
        expand_xacro(MODELS_DIR / "bin.urdf.xacro", {"name": b.name}) for b in scenario.bins if not b.model
    ]
    belt = scenario.conveyor.model_args() if scenario.conveyor is not None else {}
    for present, file, args in (
        (scenario.conveyor is not None, "conveyor.urdf.xacro", belt),
        (scenario.break_beam, "break_beam.urdf.xacro", {}),
        (scenario.deletion_wall and not scenario.deletion_wall_model, "deletion_wall.urdf.xacro", {}),
    ):
        if present:
            texts.append(expand_xacro(MODELS_DIR / file, args))
    texts += [
        expand_xacro(MODELS_DIR / "logical_camera.urdf.xacro", {"name": c.name}) for c in scenario.cameras
    ]
    # The models spawned into the world (a robot file, a launch file's spawn_model) that are
    # URDFs: a robot's own description, as its robot_state_publisher is given it.
    texts += [model.description for model in scenario.models if model.format == "urdf"]
    return texts


def robot_description(cell: Cell) -> str:
    """The cell's URDF text (see the module doc)."""
    ET.register_namespace("drake", _DRAKE_NS)
    root = ET.Element("robot", name="omtp")
    ET.SubElement(root, "link", name="world")
    # One of each name: a robot's own `world` link is the cell's, and a spawned model that
    # repeats the cell's pieces (a launch's factory URDF) adds only what the cell lacks.
    seen: dict[str, set[str]] = {"material": set(), "link": {"world"}, "joint": set()}
    for text in _model_texts(cell):
        for element in ET.fromstring(text):
            if element.tag not in seen or element.get("name") in seen[element.tag]:
                continue
            seen[element.tag].add(element.get("name", ""))
            root.append(element)
    joints = seen["joint"]
    _add_welds(cell, root, joints)
    ET.indent(root, "  ")
    return '<?xml version="1.0" ?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _add_welds(cell: Cell, root: ET.Element, known: set[str]) -> None:
    """A fixed joint for each weld of the plant that no model file has."""
    station = cell.runtime.station
    plant = station.plant
    context = plant.GetMyContextFromRoot(cell.runtime.context)
    parts = set(station.parts.values())
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        if joint.name() in known or joint.model_instance() in parts or joint.num_positions() > 0:
            continue
        parent, child = joint.parent_body(), joint.child_body()
        X_PC = plant.CalcRelativeTransform(context, parent.body_frame(), child.body_frame())
        element = ET.SubElement(root, "joint", name=joint.name(), type="fixed")
        ET.SubElement(element, "parent", link="world" if parent.index() == 0 else parent.name())
        ET.SubElement(element, "child", link=child.name())
        ET.SubElement(
            element,
            "origin",
            xyz=" ".join(f"{x:.6g}" for x in X_PC.translation()),
            rpy=" ".join(f"{x:.6g}" for x in RollPitchYaw(X_PC.rotation()).vector()),
        )
