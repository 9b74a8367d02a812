"""A scenario with a student's robot spawned in it: ``--robot FILE`` and ``Cell(robot=...)``.

Without a scenario the robot goes into Gazebo's empty world (a ground plane: the cell's
floor), as the URDF tutorial's launch file spawns it.
"""

import dataclasses
import os
from collections.abc import Sequence
from typing import Any, Optional

from omtp_drake.scenario.models import file_workspace, model_from_file
from omtp_drake.scenario.schema import Scenario

#: The world ``--robot`` spawns into without a scenario: Gazebo's empty world.
EMPTY_WORLD = "empty_world"


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
    base = scenario if scenario is not None else Scenario(name=EMPTY_WORLD, description="a ground plane")
    model = model_from_file(robot, file_workspace(robot, workspace), **placement)
    out = dataclasses.replace(base, models=[*base.models, model])
    out.validate()
    return out
