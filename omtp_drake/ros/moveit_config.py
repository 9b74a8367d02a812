"""A student's MoveIt config package on a run: ``ros-run --srdf FILE`` and
``--moveit-config DIR``.

The course's ``omtp_moveit_config`` (MoveIt Setup Assistant's output) holds
``config/<robot>.srdf`` and ``config/joint_limits.yaml``; its
``planning_context.launch`` loads them as ``/robot_description_semantic`` (the
SRDF's text) and under ``/robot_description_planning`` (the limits), next to
``/robot_description`` (the cell's URDF). :func:`install` does the same on a
session: the semantics (groups, named states, end effectors, disabled collision
pairs: :mod:`omtp_drake.ros.srdf`) and the limits go to ``session.semantic`` and
``session.joint_limits``, the texts to the parameter server. Without a config the
cell's own semantics are used (the course's named poses).

``joint_limits.yaml``: per joint ``has_velocity_limits`` / ``max_velocity`` and
``has_acceleration_limits`` / ``max_acceleration`` replace the arm's own limits
when MoveGroupCommander times a plan (a limit whose ``has_...`` is false keeps the
arm's own), and the top-level ``default_velocity_scaling_factor`` /
``default_acceleration_scaling_factor`` are the commander's starting scaling
factors, as in MoveIt. Position limits (``has_position_limits: true``) are not
supported (the planner keeps the URDF's).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from omtp_drake.errors import ConfigError, NotSupportedError
from omtp_drake.ros._core import JOINT_NAMES, tool_frame_names
from omtp_drake.ros.srdf import CellTree, SemanticModel, bad_name, default_semantic, parse_srdf

if TYPE_CHECKING:
    from omtp_drake.ros.session import Session
    from omtp_drake.script import Cell

_log = logging.getLogger("moveit_commander")

_LIMIT_KEYS = (
    "has_velocity_limits",
    "max_velocity",
    "has_acceleration_limits",
    "max_acceleration",
    "has_position_limits",
    "min_position",
    "max_position",
    "has_jerk_limits",
    "max_jerk",
)


@dataclass(frozen=True)
class JointLimits:
    """``joint_limits.yaml``: per joint its velocity and acceleration limits (None:
    the arm's own), the default scaling factors (None: not set), and the file's text."""

    velocity: Mapping[str, float] = field(default_factory=dict)
    acceleration: Mapping[str, float] = field(default_factory=dict)
    default_velocity_scaling: Optional[float] = None
    default_acceleration_scaling: Optional[float] = None
    values: Mapping[str, Any] = field(default_factory=dict)

    def arm_limits(self, joints: tuple[str, ...], velocity: np.ndarray, acceleration: np.ndarray) -> tuple:
        """The (velocity, acceleration) limits of the arm with ``joints`` (rad/s, rad/s^2):
        the file's where it sets one, else the arm's own ``velocity``/``acceleration``."""
        v = np.array([self.velocity.get(j, velocity[i]) for i, j in enumerate(joints)], dtype=float)
        a = np.array([self.acceleration.get(j, acceleration[i]) for i, j in enumerate(joints)], dtype=float)
        return v, a


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


def load_joint_limits(text: str, tree: CellTree, source: str) -> JointLimits:
    """A ``joint_limits.yaml``'s text as :class:`JointLimits` (ConfigError naming a joint
    the cell lacks, or a bad value)."""
    import yaml

    try:
        data = yaml.safe_load(text) or {}
    except yaml.YAMLError as e:
        raise ConfigError(f"{source} is not valid YAML: {e}") from None
    if not isinstance(data, dict):
        raise ConfigError(f"{source}: expected a mapping with joint_limits, got {type(data).__name__}")
    joints = {j for arm in tree.arms.values() for j in arm}
    velocity, acceleration = {}, {}
    for joint, limits in (data.get("joint_limits") or {}).items():
        if joint not in joints:
            raise bad_name(f"joint ({source})", joint, joints, closest=True)
        if not isinstance(limits, dict):
            raise ConfigError(f"{source}: joint_limits.{joint} must be a mapping, got {limits!r}")
        unknown = sorted(set(limits) - set(_LIMIT_KEYS))
        if unknown:
            raise bad_name(f"key of joint_limits.{joint} ({source})", unknown[0], _LIMIT_KEYS)
        if limits.get("has_position_limits"):
            raise NotSupportedError(
                f"{source}: joint_limits.{joint}.has_position_limits: true is not supported by omtp-drake "
                "ros-run; the planner keeps the arm's position limits (set it false)"
            )
        if limits.get("has_velocity_limits"):
            velocity[joint] = _positive(limits.get("max_velocity"), f"{source}: {joint}.max_velocity")
        if limits.get("has_acceleration_limits"):
            what = f"{source}: {joint}.max_acceleration"
            acceleration[joint] = _positive(limits.get("max_acceleration"), what)
    scales = {}
    for key in ("default_velocity_scaling_factor", "default_acceleration_scaling_factor"):
        if key in data:
            scales[key] = _positive(data[key], f"{source}: {key}")
            if scales[key] > 1:
                raise ConfigError(f"{source}: {key} must be in (0, 1], got {scales[key]}")
    return JointLimits(
        velocity,
        acceleration,
        scales.get("default_velocity_scaling_factor"),
        scales.get("default_acceleration_scaling_factor"),
        data,
    )


def _positive(value: Any, what: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a number > 0, got {value!r}") from None
    if not (number > 0 and math.isfinite(number)):
        raise ConfigError(f"{what} must be a finite number > 0, got {value!r}")
    return number


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
    from omtp_drake.cell.arms import NAMED_POSES
    from omtp_drake.ros.description import robot_description

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
