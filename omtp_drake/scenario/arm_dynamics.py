"""An arm as its file writes it, where it is not its model: each joint's velocity and
effort limit, each link's inertial, the links' geometry it replaced (fields of
:class:`~omtp_drake.scenario.configs.RobotConfig`), and their checks."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from omtp_drake.errors import ConfigError, UnknownNameError

#: An arm's links with a body (ur_description's names, after the arm's prefix).
ARM_LINKS = (
    "base_link", "shoulder_link", "upper_arm_link", "forearm_link",
    "wrist_1_link", "wrist_2_link", "wrist_3_link",
)  # fmt: skip


def check_arm_dynamics(
    where: str,
    velocity_limits: Sequence[float],
    effort_limits: Sequence[float],
    inertials: Mapping[str, Sequence[float]],
    own_geometry: Sequence[str] = (),
) -> None:
    """Raises :class:`ConfigError` (:class:`UnknownNameError` for a link) naming the robot's
    field, its value and what is valid."""
    for what, values in (("velocity_limits", velocity_limits), ("effort_limits", effort_limits)):
        if values and (len(values) != 6 or not all(0 < v < math.inf for v in values)):
            raise ConfigError(f"{where}.{what} must be 6 finite limits > 0 (or empty), got {list(values)}")
    for link, inertial in inertials.items():
        if link not in ARM_LINKS:
            raise UnknownNameError(f"link in {where}.inertials", link, ARM_LINKS)
        if len(inertial) != 10 or not all(map(math.isfinite, inertial)) or inertial[0] <= 0:
            raise ConfigError(
                f"{where}.inertials[{link}] must be [mass > 0, x, y, z, ixx, iyy, izz, ixy, ixz, iyz], "
                f"got {list(inertial)}"
            )
    valid = [f"{link}/{kind}" for link in ARM_LINKS for kind in ("visual", "collision")]
    for entry in own_geometry:
        if entry not in valid:
            raise UnknownNameError(f"entry of {where}.own_geometry", entry, valid)
