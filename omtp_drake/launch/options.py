"""The cell options every command shares, and the one door from them to a typed ``Scenario``.

Every command that builds a cell takes the same options (``omtp-drake COMMAND --help``):

- ``SCENARIO`` (positional where the command has no other) or ``--scenario NAME|FILE``: a
  scenario name of ``diagrams/``, a scenario YAML file, a robot's ``.urdf``/``.xacro``/``.sdf``
  (that robot in Gazebo's empty world) or a Gazebo ``.world`` file;
- ``--launch 'PKG FILE.launch [ARG:=VALUE ...]'`` (roslaunch's XML, or ROS 2's ``FILE.launch.py``)
  or ``--world FILE.world``: a student's own cell;
- ``--robot [NAME=]FILE[@X,Y,Z[,R,P,Y]]`` (repeatable): a robot spawned into that cell (or into
  Gazebo's empty world) as ``spawn_model -file FILE -model NAME -x X -y Y -z Z -R R -P P -Y Y``;
- ``--workspace DIR`` (repeatable): the folders their packages and models are found in;
- ``--arg NAME:=VALUE`` (repeatable): an argument of the launch file (with ``--launch``), else
  of the robot files' xacro.

:func:`cell_of` is the resolver: those options in, an :class:`OwnCell` (the typed scenario, the
warnings, a launch's nodes and MoveIt config) out; ``Cell(...)`` and every command go through it.
:func:`add_cell_options` declares the options on a command's parser; :func:`resolve_cell_options`
resolves them once, before the command runs, into ``args.scenario`` (a ``Scenario``; a file only
for a command that hands it to another process: ``grade``, an isolated ``ros-run``).
:class:`CommandParser` parses a command's line with options anywhere between its positionals.
"""

from __future__ import annotations

import argparse
import logging
import os
import shlex
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, Optional

from omtp_drake.errors import ConfigError
from omtp_drake.launch.own_cell import OwnCell, own_cell
from omtp_drake.scenario.robot_world import ROBOT_FILE_SUFFIXES, ROBOT_SYNTAX, RobotSpawn, parse_robot

if TYPE_CHECKING:
    from omtp_drake.scenario import Scenario

_log = logging.getLogger("omtp_drake")

#: What a command needs to be told, one of these.
CHOICES = (
    "a scenario (name or file), --launch 'PKG FILE.launch [ARG:=VALUE ...]', --world FILE.world "
    "or --robot FILE.urdf[.xacro]|FILE.sdf"
)


def parse_args_option(items: Sequence[str]) -> dict[str, str]:
    """``--arg NAME:=VALUE`` (roslaunch's and xacro's words; ``NAME=VALUE`` too) as a mapping."""
    out = {}
    for text in items:
        name, sep, value = text.partition(":=") if ":=" in text else text.partition("=")
        if not sep or not name:
            raise ConfigError(f"--arg {text!r}: give NAME:=VALUE")
        out[name] = value
    return out


def cell_of(
    scenario: Scenario | str | Path | None = None,
    *,
    launch: Optional[str] = None,
    world: Optional[str | os.PathLike] = None,
    robots: Sequence[RobotSpawn | str | os.PathLike] = (),
    workspace: Sequence[str | os.PathLike] | str | os.PathLike = (),
    args: Optional[dict[str, str]] = None,
    with_nodes: bool = False,
    strict_workspace: bool = True,
) -> OwnCell:
    """The cell of the options (see the module doc): the cell of at most one of ``scenario``,
    ``launch`` and ``world`` (none: Gazebo's empty world, when ``robots`` are given), with
    ``robots`` spawned in it. A ``scenario`` that is a robot file is that robot in the empty
    world; one that is a ``.world`` file is that world. ``with_nodes``: the run starts the
    launch's Python nodes itself, so the scenario's flags that stand in for them are off.
    ``strict_workspace=False``: ``workspace`` is also the command's own (``flexbe-run``'s,
    ``grade --flexbe``'s catkin folders), so a scenario without files of its own ignores it."""
    # (The schema and Drake load here, not with this module: a parser declares these options.)
    from omtp_drake.scenario import Scenario, as_scenario, scenario_from_dict, with_robot

    folders = [workspace] if isinstance(workspace, (str, os.PathLike)) else list(workspace)
    scenario, world, spawns = _sources(scenario, world, robots)
    given = [
        name for name, value in (("scenario", scenario), ("--launch", launch), ("--world", world)) if value
    ]
    if not (given or spawns):
        raise ConfigError(f"give {CHOICES}")
    if len(given) > 1:
        raise ConfigError(f"give one of {CHOICES}; got {', '.join(given)}")
    xacro_args = dict(args or {})
    if launch and xacro_args:
        launch = " ".join([launch, *(shlex.quote(f"{k}:={v}") for k, v in xacro_args.items())])
        xacro_args = {}
    elif xacro_args and not spawns:
        raise ConfigError("--arg NAME:=VALUE goes with --launch (its args) or a robot file (its xacro args)")
    if folders and not (launch or world or spawns) and strict_workspace:
        raise ConfigError(
            "--workspace goes with --launch, --world or a robot file (a scenario needs no workspace)"
        )
    if launch or world:
        cell = own_cell(launch, world, folders)
        if with_nodes and any(node.replaces for node in cell.nodes):
            name = cell.scenario.name
            document = {**cell.document_for(with_nodes=True), "models": []}  # (typed already:)
            cell.scenario = scenario_from_dict(document, source=name, name=name, models=cell.scenario.models)
        base: Optional[Scenario] = cell.scenario
    else:
        cell, base = OwnCell(Scenario()), as_scenario(scenario) if scenario else None
    for spawn in spawns:
        base = with_robot(
            base, spawn.file, folders, name=spawn.name, xyz=spawn.xyz, rpy=spawn.rpy, args=xacro_args
        )
    if base is None:  # (the check above makes sure one was given)
        raise ConfigError(f"give {CHOICES}")
    cell.scenario = base
    return cell


def _sources(
    scenario: Scenario | str | Path | None,
    world: Optional[str | os.PathLike],
    robots: Sequence[RobotSpawn | str | os.PathLike],
) -> tuple[Scenario | str | Path | None, Optional[str | os.PathLike], list[RobotSpawn]]:
    """(scenario, world, robots to spawn) of :func:`cell_of`'s arguments: a ``scenario`` that
    is a robot file is the first robot spawned (in the empty world); one that is a ``.world``
    file is the world."""
    spawns = [r if isinstance(r, RobotSpawn) else parse_robot(os.fspath(r)) for r in robots]
    if isinstance(scenario, (str, os.PathLike)) and str(scenario).endswith(ROBOT_FILE_SUFFIXES):
        spawns.insert(0, RobotSpawn(os.fspath(scenario)))
        scenario = None
    elif isinstance(scenario, (str, os.PathLike)) and str(scenario).endswith(".world") and not world:
        scenario, world = None, scenario
    return scenario, world, spawns


def chosen_cell(
    scenario: Scenario | str | Path | None = None,
    *,
    launch: str | None = None,
    world: str | os.PathLike | None = None,
    workspace: Sequence[str | os.PathLike] | str | os.PathLike = (),
) -> OwnCell:
    """The cell of exactly one of ``scenario``, ``launch`` and ``world`` (``workspace``: the
    folders a launch or world finds its packages and models in): :func:`cell_of` without robots."""
    if not (scenario or launch or world):
        raise ConfigError(f"give {CHOICES}")
    return cell_of(scenario, launch=launch, world=world, workspace=workspace)


def add_cell_options(p: argparse.ArgumentParser, *, positional: bool = False, workspace: bool = True) -> None:
    """Declares the cell options (see the module doc) on ``p``: ``positional``: SCENARIO as a
    positional too (a command with no other positional); ``workspace=False``: the command has
    its own ``--workspace`` of catkin folders, which the launch, world and robots use too."""
    if positional:
        p.add_argument(
            "scenario", metavar="SCENARIO", nargs="?", help="a scenario name or file (or --scenario)"
        )
    p.add_argument(
        "--scenario",
        dest="scenario_option",
        metavar="NAME|FILE",
        help="the cell: a scenario name or YAML file, a robot's URDF/xacro/SDF file (in Gazebo's empty "
        "world) or a Gazebo .world file",
    )
    p.add_argument(
        "--launch",
        metavar="'PKG FILE.launch [ARG:=VALUE ...]'",
        help="the cell of a student's launch file (as roslaunch takes it; a ROS 2 FILE.launch.py as ros2 "
        "launch does), instead of a scenario",
    )
    p.add_argument("--world", metavar="FILE.world", help="the cell of a student's Gazebo world file")
    p.add_argument(
        "--robot",
        action="append",
        default=[],
        metavar=ROBOT_SYNTAX,
        help="spawn this URDF, xacro or SDF robot into the cell (without a scenario, launch or world: "
        "into Gazebo's empty world) as spawn_model -model NAME -x X -y Y -z Z -R R -P P -Y Y does "
        "(m, rad; repeatable)",
    )
    if workspace:
        p.add_argument(
            "--workspace",
            action="append",
            default=[],
            metavar="DIR",
            help="a catkin/colcon src folder or a package the launch, world or robot finds packages and "
            "models in (repeatable; ROS_PACKAGE_PATH and GAZEBO_MODEL_PATH are read too)",
        )
    p.add_argument(
        "--arg",
        dest="cell_args",
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="an argument of the --launch file, else of the robot files' xacro (repeatable)",
    )
    p.set_defaults(cell_workspace_option=workspace)


def resolve_cell_options(args: argparse.Namespace, warn: Optional[Callable[[str], Any]] = None) -> None:
    """Resolves the cell options of ``args`` with :func:`cell_of`, once, before the command
    runs: ``args.scenario`` becomes the typed ``Scenario`` (for a command that hands it to
    another process, ``args.cell_file`` or an isolated run's ``args.sandbox``: the scenario's
    name or file as given, or a file written for it that lives as long as the command);
    ``args.moveit_config`` the launch's own MoveIt config, unless given; ``args.nodes`` (a
    command that runs a launch's nodes in its session) the ROS 1 nodes, ``args.ros2_nodes``
    (``ros2``) the workspace's ROS 2 nodes. Each warning line goes to ``warn`` (default: the log)."""
    if not hasattr(args, "cell_workspace_option"):
        return  # a command that takes no cell (add_cell_options was not called on its parser)
    positional, option = getattr(args, "scenario", None), args.scenario_option
    if positional and option and positional != option:
        raise ConfigError(
            f"the scenario is given twice ({positional!r} and --scenario {option!r}); give it once"
        )
    scenario = positional or option
    isolated = getattr(args, "sandbox", None) is not None
    with_nodes = getattr(args, "nodes", None) is not None and not isolated
    cell = cell_of(
        scenario,
        launch=args.launch,
        world=args.world,
        robots=[parse_robot(r) for r in args.robot],
        workspace=args.workspace or (),
        args=parse_args_option(args.cell_args),
        with_nodes=with_nodes,
        strict_workspace=args.cell_workspace_option,
    )
    with_ros2_nodes = getattr(args, "ros2_nodes", None) is not None
    not_run = ([] if with_nodes else cell.ros_only) + ([] if with_ros2_nodes else cell.ros2_only)
    for line in cell.warnings + not_run:
        (warn or _log.warning)(line)
    if with_nodes:
        args.nodes = [(node.path, node.argv) for node in cell.nodes if node.program is None]
    if with_ros2_nodes:
        args.ros2_nodes = [node for node in cell.nodes if node.program is not None]
    if cell.moveit_config is not None and getattr(args, "moveit_config", "absent") is None:
        args.moveit_config = str(cell.moveit_config)
    args.scenario = cell.scenario
    if getattr(args, "cell_file", False) or isolated:
        own_files = (
            args.launch
            or args.world
            or args.robot
            or str(scenario).endswith((*ROBOT_FILE_SUFFIXES, ".world"))
        )
        plain = scenario and not own_files
        args.scenario = str(scenario) if plain else str(_write(cell.scenario, args))


def _write(scenario: Scenario, args: argparse.Namespace) -> Path:
    """``scenario`` as a YAML file in a folder that lives as long as ``args`` (the command)."""
    from pydrake.common.yaml import yaml_dump_typed

    folder = tempfile.TemporaryDirectory(prefix="omtp_cell_")
    args._cell_folder = folder  # removed when the command ends
    path = Path(folder.name) / f"{scenario.name or 'cell'}.yaml"
    path.write_text(yaml_dump_typed(scenario))
    return path


class CommandParser(argparse.ArgumentParser):
    """argparse whose errors are one line (exit 2), like every other error of the CLI, and whose
    commands take their options anywhere between their positionals (``tf-echo SCENARIO --time
    1.5 SOURCE TARGET``), as :meth:`~argparse.ArgumentParser.parse_intermixed_args` parses them."""

    _intermixing = False

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message}\n")

    def parse_known_args(self, args: Any = None, namespace: Any = None) -> Any:
        whole = (argparse.PARSER, argparse.REMAINDER)
        if self._intermixing or any(a.nargs in whole for a in self._get_positional_actions()):
            return super().parse_known_args(args, namespace)
        self._intermixing = True  # parse_known_intermixed_args calls parse_known_args twice
        try:
            return super().parse_known_intermixed_args(args, namespace)
        finally:
            self._intermixing = False
