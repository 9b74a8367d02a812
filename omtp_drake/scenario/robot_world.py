"""A scenario with a student's robot spawned in it: ``--robot FILE`` and ``Cell(robot=...)``.

Without a scenario the robot goes into Gazebo's empty world (a ground plane: the cell's
floor), as the URDF tutorial's launch file spawns it.

``--robot``'s syntax and parser are here without the schema (a command line declares and
reads its options without importing Drake); :func:`with_robot` imports it when called.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from omtp_drake.scenario.schema import Scenario

#: The world ``--robot`` spawns into without a scenario: Gazebo's empty world.
EMPTY_WORLD = "empty_world"
#: File names that are a robot's description, not a scenario.
ROBOT_FILE_SUFFIXES = (".urdf", ".xacro", ".sdf")
#: ``--robot``'s syntax, as its help and its errors say it.
ROBOT_SYNTAX = "[NAME=]FILE[@X,Y,Z[,R,P,Y]]"


def with_robot(
    scenario: Optional[Scenario],
    robot: str | os.PathLike,
    workspace: Sequence[str | os.PathLike] = (),
    **placement: Any,
) -> Scenario:
    """``scenario`` (None: Gazebo's empty world) with the robot of the URDF, xacro or SDF
    file ``robot`` spawned in it as ``spawn_model`` spawns it; its packages are found in the
    folders ``workspace`` and next to it. ``placement``: ``model_from_file``'s ``name``,
    ``xyz``, ``rpy``, ``args``."""
    from omtp_drake.scenario.models import file_workspace, model_from_file
    from omtp_drake.scenario.schema import Scenario

    base = scenario if scenario is not None else Scenario(name=EMPTY_WORLD, description="a ground plane")
    model = model_from_file(robot, file_workspace(robot, workspace), **placement)
    out = dataclasses.replace(base, models=[*base.models, model])
    out.validate()
    return out


@dataclasses.dataclass(frozen=True)
class RobotSpawn:
    """One ``--robot``: a description file spawned as ``spawn_model`` spawns it."""

    file: str
    #: ``-model`` (empty: the file's robot or model name).
    name: str = ""
    #: ``-x -y -z`` (m) and ``-R -P -Y`` (rad).
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)


def parse_robot(text: str) -> RobotSpawn:
    """``[NAME=]FILE[@X,Y,Z[,R,P,Y]]`` as a :class:`RobotSpawn`; ConfigError naming the bad part."""
    name, sep, rest = text.partition("=")
    if not sep or "/" in name or not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        name, rest = "", text
    file, at, pose = rest.rpartition("@") if "@" in rest else (rest, "", "")
    if not file:
        raise ConfigError(f"--robot {text!r}: give {ROBOT_SYNTAX}, e.g. robot.urdf.xacro@1,0,0.5,0,0,1.57")
    values: list[float] = []
    if at:
        try:
            values = [float(v) for v in pose.split(",")]
        except ValueError:
            values = []
        if len(values) not in (3, 6) or not all(math.isfinite(v) for v in values):
            raise ConfigError(
                f"--robot {text!r}: the placement {pose!r} is not X,Y,Z or X,Y,Z,R,P,Y (finite numbers, "
                "m and rad, as spawn_model's -x -y -z -R -P -Y)"
            )
    xyz = tuple(values[:3]) if values else (0.0, 0.0, 0.0)
    rpy = tuple(values[3:]) if len(values) == 6 else (0.0, 0.0, 0.0)
    return RobotSpawn(file, name, xyz, rpy)  # type: ignore[arg-type]
