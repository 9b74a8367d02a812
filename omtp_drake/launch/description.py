"""The robot description a student's launch file loads, for ``omtp-drake view --launch``.

rviz's RobotModel display (and ``joint_state_publisher_gui``) show the URDF on the
parameter ``robot_description``; the course's lecture-1 launch loads the factory's
xacro there (``<param name="robot_description" command="$(find xacro)/xacro ..."/>``).
:func:`launch_description` reads the launch as ``roslaunch`` would and returns that
parameter's model, its ``package://`` and ``model://`` URIs found in the workspace.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import WorkspaceError

if TYPE_CHECKING:
    from omtp_drake.scenario import ModelConfig

# The readers are imported when a description is read: the CLI hands these functions to
# ``view``'s parser, and a command line that runs another command never reads one.

#: The parameter rviz's RobotModel display reads by default.
ROBOT_DESCRIPTION = "/robot_description"


def launch_description(
    spec: str, workspace: Sequence[str | os.PathLike] = (), param: str = ROBOT_DESCRIPTION
) -> ModelConfig:
    """The model on parameter ``param`` of the launch ``spec`` (``'PKG FILE.launch
    [ARG:=VALUE ...]'``) in ``workspace``; WorkspaceError naming the launch and the
    description parameters it has when ``param`` is not one of them."""
    from omtp_drake.launch.launch_py import read_launch_file
    from omtp_drake.launch.own_cell import student_workspace
    from omtp_drake.launch.roslaunch import find_launch_file, parse_launch_spec
    from omtp_drake.scenario import model_from_text

    ws = student_workspace(workspace)
    pkg, file, args = parse_launch_spec(spec)
    path = find_launch_file(ws, pkg, file)
    params = read_launch_file(path, args, ws).params
    name = "/" + param.strip("/")
    descriptions = {k: v for k, v in _flat(params) if isinstance(v, str) and _is_description(v)}
    if name not in descriptions:
        valid = ", ".join(sorted(descriptions)) or "none"
        raise WorkspaceError(f"{path}: loads no robot description on {name}; description parameters: {valid}")
    return model_from_text(descriptions[name], f"{path} ({name})", ws, static=True)


def _flat(params: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    """(full name, value) of every parameter of the nested ``params``."""
    for key, value in params.items():
        name = f"{prefix}/{key}"
        if isinstance(value, Mapping):
            yield from _flat(value, name)
        else:
            yield name, value


def _is_description(text: str) -> bool:
    """Whether ``text`` is a URDF or SDF document (its root element ``robot`` or ``sdf``)."""
    if not text.lstrip().startswith("<"):
        return False
    try:
        return ET.fromstring(text).tag in ("robot", "sdf")
    except ET.ParseError:
        return False


def world_description(
    path: str | os.PathLike, workspace: Sequence[str | os.PathLike] = ()
) -> tuple[list[ModelConfig], list[str]]:
    """Every model of the Gazebo world ``path`` as it is in its file (the course's pieces
    too, for ``omtp-drake view FILE.world``), its ``model://`` includes found in
    ``workspace``, ``GAZEBO_MODEL_PATH`` and the package holding the world; and the lines
    sdformat would warn with."""
    from omtp_drake.launch.own_cell import student_workspace
    from omtp_drake.launch.sdf_world import model_config, read_world

    world_file = Path(path).expanduser().resolve()
    own = [f for f in world_file.parents if (f / "package.xml").is_file()][:1]
    ws = student_workspace([*workspace, *own])
    world = read_world(world_file, ws)
    return [model_config(model, ws) for model in world.models], world.warnings
