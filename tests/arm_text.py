"""A bare six-joint arm's URDF, written here for the loader's limit tests: ur_description's
joint names under a prefix, each joint's ``<limit>`` attributes given per joint."""

from __future__ import annotations

from collections.abc import Callable

from omtp_drake.launch.arm_dynamics import ARM_JOINTS
from omtp_drake.launch.urdf_model import UrdfModel


def arm_with_limits(limit: Callable[[int], str], prefix: str = "r_") -> UrdfModel:
    """The arm ``r`` (a chain-less tree: every joint from link ``a``), joint ``k``'s limit
    element carrying the attributes ``limit(k)``; read as from ``arm.urdf``."""
    joints = "".join(
        f'<joint name="{prefix}{j}" type="revolute"><parent link="a"/><child link="b{k}"/>'
        f"<limit {limit(k)}/></joint>"
        for k, j in enumerate(ARM_JOINTS)
    )
    links = "".join(f'<link name="b{k}"/>' for k in range(len(ARM_JOINTS)))
    return UrdfModel.from_text(f'<robot name="r"><link name="a"/>{links}{joints}</robot>', "arm.urdf")
