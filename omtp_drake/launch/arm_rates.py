"""An arm's joint velocity and effort limits as the student's URDF writes them.

ur_description writes each joint's ``<limit velocity=... effort=...>``; Gazebo's
``gazebo_ros_control`` bounds the joint's commands by them, MoveIt reads the velocities
into the robot model (its ``joint_limits.yaml`` may override them) and the course's
trajectories are timed within them. A student who changes them (a slower arm, a weaker
wrist) gets them in the scenario's ``RobotConfig.velocity_limits`` / ``effort_limits``:
DiffIK, the planners' timing, MoveIt's limits and the plant's actuators take them there.
Limits equal to the model's (ur_description's, :func:`omtp_drake.ur_arms.model_rates`)
leave the fields empty, so the course's files give the built-in scenario.
"""

from __future__ import annotations

import math

from omtp_drake.launch.urdf_model import UrdfModel
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
