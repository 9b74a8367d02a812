"""A student's MoveIt config package on a run: ``ros-run --srdf FILE`` and
``--moveit-config DIR``.

The course's ``omtp_moveit_config`` (MoveIt Setup Assistant's output) holds
``config/<robot>.srdf`` and ``config/joint_limits.yaml``; its
``planning_context.launch`` loads them as ``/robot_description_semantic`` (the
SRDF's text) and under ``/robot_description_planning`` (the limits), next to
``/robot_description`` (the cell's URDF). :func:`install` does the same on a
session: the semantics (groups, named states, end effectors, disabled collision
pairs: :mod:`omtp_drake.ros.moveit.srdf`) and the limits go to ``session.semantic`` and
``session.joint_limits``, the texts to the parameter server. Without a config the
cell's own semantics are used (the course's named poses).

``joint_limits.yaml``: see :mod:`omtp_drake.ros.moveit.joint_limits`.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import JOINT_NAMES, tool_frame_names
from omtp_drake.ros.moveit.joint_limits import load_joint_limits
from omtp_drake.ros.moveit.srdf import CellTree, SemanticModel, default_semantic, parse_srdf

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell
    from omtp_drake.ros.comm.session import Session

_log = logging.getLogger("moveit_commander")


def cell_tree(cell: Cell) -> CellTree:
    """The cell's kinematic tree (its plant's joints; parts left out)."""
    station = cell.runtime.station
    plant = station.plant
    parts = set(station.parts.values())
    parent = {}
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        if joint.model_instance() in parts:
            continue
        parent[joint.child_body().name()] = (
            joint.name(),
            joint.parent_body().name(),
            joint.num_positions() > 0,
        )
    arms = {r: tuple(f"{r}_{j}" for j in JOINT_NAMES) for r in station.arms}
    tools = {}
    for robot, handles in station.arms.items():
        names = tool_frame_names(handles.config)
        tools[robot] = tuple(dict.fromkeys([names.get("suction_cup", names["tool0"]), *names.values()]))
    return CellTree(parent, arms, tools)


def config_files(
    srdf: Optional[str | Path], package: Optional[str | Path]
) -> tuple[Optional[Path], Optional[Path]]:
    """(the SRDF, the joint_limits.yaml) of ``--srdf FILE`` and ``--moveit-config DIR``
    (``DIR/config/*.srdf``, ``DIR/config/joint_limits.yaml``); ``--srdf`` wins."""
    limits = None
    if package is not None:
        config = Path(package) / "config"
        if not config.is_dir():
            raise ConfigError(
                f"--moveit-config {str(package)!r} has no config/ folder (a MoveIt config package has)"
            )
        found = sorted(config.glob("*.srdf"))
        if srdf is None:
            if len(found) != 1:
                names = ", ".join(p.name for p in found) or "none"
                raise ConfigError(
                    f"--moveit-config {str(package)!r}: config/ must hold one .srdf file, found: {names}; "
                    "choose one with --srdf FILE"
                )
            srdf = found[0]
        limits = config / "joint_limits.yaml" if (config / "joint_limits.yaml").is_file() else None
    if srdf is not None and not Path(srdf).is_file():
        raise ConfigError(f"--srdf {str(srdf)!r} does not exist")
    return (Path(srdf) if srdf is not None else None), limits


def install(
    session: Session,
    srdf: Optional[str | Path] = None,
    package: Optional[str | Path] = None,
) -> SemanticModel:
    """Gives ``session`` its semantics (returned) and joint limits and sets
    ``/robot_description``, ``/robot_description_semantic`` and
    ``/robot_description_planning/...`` (see the module doc)."""
    from omtp_drake.ros.comm._core import NAMED_POSES
    from omtp_drake.ros.moveit.description import robot_description

    cell = session.cell
    tree = cell_tree(cell)
    srdf_path, limits_path = config_files(srdf, package)
    if srdf_path is not None:
        semantic = parse_srdf(srdf_path.read_text(), tree, srdf_path.name)
    else:
        poses = {
            r: {k: v for k, v in NAMED_POSES.items() if k.startswith(cell.arm(r).config.pose_prefix)}
            for r in tree.arms
        }
        semantic = default_semantic(tree, poses)
    limits = load_joint_limits(limits_path.read_text(), tree, limits_path.name) if limits_path else None
    session.semantic = semantic
    session.joint_limits = limits
    session.params["/robot_description"] = robot_description(cell)
    session.params["/robot_description_semantic"] = semantic.text
    if limits is not None:
        for key, value in _flatten(limits.values, "/robot_description_planning"):
            session.params[key] = value
    return semantic


def semantics(session: Session) -> SemanticModel:
    """The session's semantics (the cell's own ones installed first if it has none)."""
    return session.semantic if session.semantic is not None else install(session)


def end_effector_link(semantic: SemanticModel, group: str, links: Mapping[str, str]) -> str:
    """The SRDF's end-effector link of ``group`` if it is one of the arm's tool frames
    ``links`` (full name -> short name); else the course's suction cup (logged)."""
    cup = next((f for f, s in links.items() if s == "suction_cup"), next(iter(links)))
    link = semantic.end_effector_link(group)
    if link is None or link in links:
        return link or cup
    _log.warning(
        "%s: end-effector link %s is no tool frame of the cell (%s); using %s",
        group,
        link,
        ", ".join(links),
        cup,
    )
    return cup


def arm_joint_limits(session: Session, robot: str, planner: Any) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """The (velocity, acceleration) limits the run's joint_limits.yaml gives ``robot``
    (the arm's own, ``planner``'s, where it sets none); None when it sets none of them."""
    limits = session.joint_limits
    joints = tuple(f"{robot}_{j}" for j in JOINT_NAMES)
    if limits is None or not any(j in limits.velocity or j in limits.acceleration for j in joints):
        return None
    return limits.arm_limits(joints, planner.velocity_limits, planner.acceleration_limits)


def _flatten(data: Mapping[str, Any], prefix: str) -> list[tuple[str, Any]]:
    """(name, value) of every leaf of ``data`` under ``prefix``, as rosparam loads a file."""
    out: list[tuple[str, Any]] = []
    for key, value in data.items():
        name = f"{prefix}/{key}"
        if isinstance(value, dict):
            out += _flatten(value, name)
        else:
            out.append((name, value))
    return out
