"""The options every command that takes a cell shares: a scenario, or a student's own
files (``--launch 'PKG FILE.launch [ARG:=VALUE ...]'`` or ``--world FILE.world``, with
``--workspace DIR``, repeatable), and the one function that turns them into a cell.

:func:`chosen_cell` is that function for the Python API (``Cell(launch=...,
workspace=...)``) and the commands; another source of a cell (a robot file) goes
beside the launch and world here. :func:`add_cell_options` declares the options on a
command's parser; :func:`resolve_cell_options` turns them into the scenario file the
command loads (written to a temporary folder that lives as long as the command), and
into the run's MoveIt config when the launch names the student's own, and for ros-run
(``args.nodes``) into the workspace's Python nodes it runs in its session.
"""

from __future__ import annotations

import argparse
import logging
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from omtp_drake.errors import ConfigError
from omtp_drake.launch.own_cell import OwnCell, own_cell
from omtp_drake.scenario import Scenario, as_scenario

_log = logging.getLogger("omtp_drake")

#: What a command needs to be told, one of these.
CHOICES = "a scenario (name or file), --launch 'PKG FILE.launch [ARG:=VALUE ...]' or --world FILE.world"


def chosen_cell(
    scenario: Scenario | str | Path | None = None,
    *,
    launch: str | None = None,
    world: str | os.PathLike | None = None,
    workspace: Sequence[str | os.PathLike] | str | os.PathLike = (),
) -> OwnCell:
    """The cell of exactly one of ``scenario``, ``launch`` and ``world`` (``workspace``: the
    folders a launch or world finds its packages and models in)."""
    given = [name for name, value in (("scenario", scenario), ("launch", launch), ("world", world)) if value]
    if len(given) != 1:
        raise ConfigError(f"give one of {CHOICES}; got {', '.join(given) or 'none'}")
    if scenario:
        if workspace:
            raise ConfigError("--workspace goes with --launch or --world (a scenario needs no workspace)")
        return OwnCell(as_scenario(scenario))
    return own_cell(launch, world, workspace)


def add_scenario_argument(p: argparse.ArgumentParser) -> None:
    """SCENARIO (optional), or a student's own files instead: ``--launch`` / ``--world`` with
    ``--workspace``."""
    p.add_argument("scenario", metavar="SCENARIO", nargs="?", help="a scenario name or file")
    add_cell_options(p)


def add_cell_options(p: argparse.ArgumentParser, *, workspace: bool = True) -> None:
    """Declares ``--launch``, ``--world`` and ``--workspace`` on ``p`` (``workspace=False``: the
    command has its own ``--workspace`` of catkin folders, which the launch uses too)."""
    p.add_argument(
        "--launch",
        metavar="'PKG FILE.launch [ARG:=VALUE ...]'",
        help="the cell of a student's launch file (as roslaunch takes it), instead of a scenario",
    )
    p.add_argument("--world", metavar="FILE.world", help="the cell of a student's Gazebo world file")
    p.set_defaults(cell_workspace_option=workspace)
    if not workspace:
        return
    p.add_argument(
        "--workspace",
        action="append",
        default=[],
        metavar="DIR",
        help="a catkin/colcon src folder or a package the launch or world finds packages and models in "
        "(repeatable; ROS_PACKAGE_PATH and GAZEBO_MODEL_PATH are read too)",
    )


def resolve_cell_options(args: argparse.Namespace, warn: Any = None) -> None:
    """With ``--launch`` or ``--world``: ``args.scenario`` becomes the file of their cell (and
    ``args.moveit_config`` the launch's own MoveIt config, unless given); each warning line
    goes to ``warn`` (default: the log). Without them: a scenario must be given."""
    if not hasattr(args, "cell_workspace_option"):
        return  # a command that takes no cell (add_cell_options was not called on its parser)
    launch, world = args.launch, args.world
    if not (launch or world):
        if getattr(args, "robot", None):
            return  # the robot's own world, or the scenario's (its workspace is the robot's)
        if not getattr(args, "scenario", None):
            raise ConfigError(f"give {CHOICES}")
        if getattr(args, "workspace", None) and getattr(args, "cell_workspace_option", False):
            chosen_cell(args.scenario, workspace=args.workspace)  # the error says why
        return
    cell = chosen_cell(args.scenario or None, launch=launch, world=world, workspace=args.workspace or ())
    # ros-run and flexbe-run (not isolated) run the workspace's nodes in their session; the others cannot.
    with_nodes = getattr(args, "nodes", None) is not None and getattr(args, "sandbox", None) is None
    for line in cell.warnings + ([] if with_nodes else cell.ros_only):
        (warn or _log.warning)(line)
    folder = tempfile.TemporaryDirectory(prefix="omtp_own_cell_")
    args._own_cell_folder = folder  # removed when the command ends
    args.scenario = str(cell.write(folder.name, with_nodes=with_nodes))
    if with_nodes:
        args.nodes = [(node.path, node.argv) for node in cell.nodes]
    if cell.moveit_config is not None and getattr(args, "moveit_config", "absent") is None:
        args.moveit_config = str(cell.moveit_config)
