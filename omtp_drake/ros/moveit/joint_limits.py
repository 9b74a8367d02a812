"""MoveIt's ``joint_limits.yaml`` of a MoveIt config package.

Per joint, ``has_velocity_limits`` / ``max_velocity`` and ``has_acceleration_limits``
/ ``max_acceleration`` replace the arm's own limits when a plan is timed (a limit
whose ``has_...`` is false keeps the arm's own); the top-level
``default_velocity_scaling_factor`` / ``default_acceleration_scaling_factor`` are a
MoveGroupCommander's starting scaling factors, as in MoveIt. Position limits
(``has_position_limits: true``) are not supported: the planner keeps the URDF's.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from omtp_drake.errors import ConfigError, NotSupportedError, check_positive
from omtp_drake.ros.moveit.srdf import CellTree, bad_name

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
            velocity[joint] = check_positive(f"{source}: {joint}.max_velocity", limits.get("max_velocity"))
        if limits.get("has_acceleration_limits"):
            what = f"{source}: {joint}.max_acceleration"
            acceleration[joint] = check_positive(what, limits.get("max_acceleration"))
    scales = {}
    for key in ("default_velocity_scaling_factor", "default_acceleration_scaling_factor"):
        if key in data:
            scales[key] = check_positive(f"{source}: {key}", data[key])
            if scales[key] > 1:
                raise ConfigError(f"{source}: {key} must be in (0, 1], got {scales[key]}")
    return JointLimits(
        velocity,
        acceleration,
        scales.get("default_velocity_scaling_factor"),
        scales.get("default_acceleration_scaling_factor"),
        data,
    )
