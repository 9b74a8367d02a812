"""An arm's joint velocity and effort limits, and its links' inertia, as the student's URDF
writes them.

ur_description writes each joint's ``<limit velocity=... effort=...>``; Gazebo's
``gazebo_ros_control`` bounds the joint's commands by them, MoveIt reads the velocities
into the robot model (its ``joint_limits.yaml`` may override them) and the course's
trajectories are timed within them. A student who changes them (a slower arm, a weaker
wrist) gets them in the scenario's ``RobotConfig.velocity_limits`` / ``effort_limits``:
DiffIK, the planners' timing, MoveIt's limits and the plant's actuators take them there.
Limits equal to the model's (ur_description's, :func:`omtp_drake.ur_arms.model_rates`)
leave the fields empty, so the course's files give the built-in scenario.

Its links' ``<inertial>`` (mass, centre of mass, inertia): where a link's differs from
what the course's ``ur_description`` gives it (the project's stand-in, expanded for the
same model), it is the scenario's ``RobotConfig.inertials`` and the plant's arm (and its
servo's model) has it, as Gazebo takes a link's inertial as written. One the plant cannot
take (a mass not > 0, an inertia no body can have) is one warning, and the arm keeps
its model's.
"""

from __future__ import annotations

import functools
import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from pydrake.math import RollPitchYaw
from pydrake.multibody.tree import RotationalInertia

from omtp_drake.assets import cache_entry, write_atomic
from omtp_drake.launch.urdf_model import UrdfModel
from omtp_drake.scenario.arm_dynamics import ARM_LINKS
from omtp_drake.ur_arms import model_rates

#: An arm's six joints, after its prefix (ur_description's order).
ARM_JOINTS = (
    "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
    "wrist_1_joint", "wrist_2_joint", "wrist_3_joint",
)  # fmt: skip


def arm_joint_rates(model: UrdfModel, prefix: str, kind: str, where: str) -> tuple[dict, list[str]]:
    """The arm's velocity and effort limits as the scenario's robot fields (only those
    that differ from the ``kind`` arm's: ``ur5``, ``ur10``), and a warning line for each
    attribute whose values the cell's arm cannot take (not a number > 0: it keeps the
    model's, naming the launch line and the joints' values)."""
    root = model.root_element
    defaults = dict(zip(("velocity", "effort"), model_rates(kind)))
    out: dict = {}
    lines: list[str] = []
    for attribute, default in defaults.items():
        written: list[str] = []
        for name in ARM_JOINTS:
            element = root.find(f"joint[@name='{prefix}{name}']/limit") if root is not None else None
            value = element.get(attribute) if element is not None else None
            if value is None:
                break
            written.append(value)
        if len(written) < len(ARM_JOINTS):
            continue  # (a joint without the attribute: the model's, as the course's files give)
        values = [_number(v) for v in written]
        if not all(0 < v < math.inf for v in values):
            joints = ", ".join(f"{n} {v}" for n, v in zip(ARM_JOINTS, written))
            lines.append(
                f"{where}: arm {prefix.rstrip('_')!r}: {attribute} limits {joints} are not all numbers > 0; "
                f"the cell's arm keeps {kind}'s {' '.join(f'{d:g}' for d in default)}"
            )
        elif any(abs(v - d) > 1e-9 * max(1.0, d) for v, d in zip(values, default)):
            out[f"{attribute}_limits"] = values
    return out, lines


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def arm_inertials(model: UrdfModel, prefix: str, kind: str, where: str) -> tuple[dict, list[str]]:
    """The arm's links' inertials that differ from the course's ``kind`` arm's, as the
    scenario's robot field ``inertials`` (link -> mass, centre of mass, inertia about it
    in the link's axes: :attr:`~omtp_drake.scenario.RobotConfig.inertials`), and a warning
    line for each one the plant cannot take."""
    root = model.root_element
    course = course_inertials(kind)
    out: dict[str, list[float]] = {}
    lines: list[str] = []
    for link in ARM_LINKS:
        element = root.find(f"link[@name='{prefix}{link}']/inertial") if root is not None else None
        if element is None:
            continue
        values = _inertial(element)
        known = course.get(link)
        if known is not None and np.allclose(values, known, rtol=1e-9, atol=1e-12, equal_nan=False):
            continue
        if not _takes(values):
            lines.append(
                f"{where}: arm {prefix.rstrip('_')!r}: link {link}'s inertial (mass {values[0]:g}, "
                f"inertia {' '.join(f'{v:g}' for v in values[4:])}) is no body's; "
                f"the cell's arm keeps {kind}'s"
            )
            continue
        out[link] = values
    return ({"inertials": out} if out else {}), lines


#: Bump when what :func:`course_inertials` keeps in the model cache changes.
_KEPT_INERTIALS = "1"


@functools.cache
def course_inertials(kind: str) -> dict[str, list[float]]:
    """The inertials the course's ``ur_description`` gives a ``kind`` arm's links (the
    project's stand-in, expanded for that model). Kept in the model cache by the stand-ins'
    content (their folder's name), xacro's version and ``kind``: a command's first read of a
    launch expanded the stand-in again (a workspace, its prefix, the kept expansion's hashes)."""
    from omtp_drake.assets import xacro_version
    from omtp_drake.launch.standins import standin_dirs

    (standins,) = standin_dirs()
    kept = cache_entry(f"course-inertials/{standins.name}-{xacro_version()}-{_KEPT_INERTIALS}-{kind}.json")
    try:
        values = json.loads(kept.read_text())
        return {str(link): [float(v) for v in numbers] for link, numbers in values.items()}
    except (OSError, ValueError, AttributeError, TypeError):
        pass
    out = _expanded_inertials(kind, standins)
    write_atomic(kept, json.dumps(out).encode())
    return out


def _expanded_inertials(kind: str, standins: Path) -> dict[str, list[float]]:
    """:func:`course_inertials` of the stand-ins in ``standins``, expanded with xacro."""
    from omtp_drake.workspace import Workspace, expand_xacro_in

    workspace = Workspace.from_dirs((), environ={}, bundled=(standins,))
    call = cache_entry(f"course_{kind}_arm.urdf.xacro")
    if not call.exists():
        write_atomic(
            call,
            (
                '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                f'<xacro:include filename="$(find ur_description)/urdf/{kind}.urdf.xacro"/>'
                f'<xacro:{kind}_robot prefix="" joint_limited="true"/></robot>'
            ).encode(),
        )
    root = ET.fromstring(expand_xacro_in(workspace, call))
    return {
        link: _inertial(element)
        for link in ARM_LINKS
        if (element := root.find(f"link[@name='{link}']/inertial")) is not None
    }


def _inertial(element: ET.Element) -> list[float]:
    """A URDF ``<inertial>`` as [mass, x, y, z, ixx, iyy, izz, ixy, ixz, iyz]: its centre of
    mass and its inertia about it in the link's axes (its ``origin``'s rotation applied)."""
    mass = element.find("mass")
    origin = element.find("origin")
    inertia = element.find("inertia")
    m = _number(mass.get("value", "nan")) if mass is not None else math.nan
    xyz = [_number(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
    rpy = [_number(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
    keys = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    i = {k: _number(inertia.get(k, "0")) if inertia is not None else math.nan for k in keys}
    I_I = np.array(
        [[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]]
    )
    if len(xyz) != 3 or len(rpy) != 3:
        return [m, *([math.nan] * 9)]
    finite = all(map(math.isfinite, rpy))
    R_LI = RollPitchYaw(rpy).ToRotationMatrix().matrix() if finite else np.full((3, 3), math.nan)
    I_L = R_LI @ I_I @ R_LI.T
    moments = [I_L[0, 0], I_L[1, 1], I_L[2, 2], I_L[0, 1], I_L[0, 2], I_L[1, 2]]
    return [m, *xyz, *(float(v) for v in moments)]


def _takes(values: list[float]) -> bool:
    """Whether the plant can take the inertial ``values`` (a body's: mass > 0, inertia valid)."""
    if not all(map(math.isfinite, values)) or values[0] <= 0:
        return False
    return bool(RotationalInertia(*values[4:]).CouldBePhysicallyValid())
