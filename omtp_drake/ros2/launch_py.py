"""``omtp-drake ros2 --launch 'PKG FILE.launch.py [ARG:=VALUE ...]'``: a ROS 2 launch file
evaluated as ``ros2 launch`` evaluates it (the in-house API of :mod:`omtp_drake.ros2.launch_api`),
its nodes mapped to the cell:

========================================  ==========================================================
in the launch                             here
========================================  ==========================================================
``DeclareLaunchArgument``, ``ARG:=V``      launch configurations (an include sees its parent's)
``IncludeLaunchDescription`` of a         evaluated; gazebo_ros's ``gazebo.launch.py`` (or
``PythonLaunchDescriptionSource``         ``gzserver``) is the cell's world: ``world:=FILE``, else
                                          Gazebo's empty world
``Node`` robot_state_publisher            its ``robot_description`` is the robot the cell spawns
                                          (its ``/tf`` is the cell's own)
``Node`` gazebo_ros ``spawn_entity.py``   the robot spawned: ``-topic robot_description`` or
                                          ``-file``, ``-entity NAME``, ``-x -y -z -R -P -Y``
``TimerAction``, ``RegisterEventHandler``  their actions, in order (the cell starts all at once)
(``OnProcessExit``), ``GroupAction``
any other ``Node``, ``ExecuteProcess``    not run: one warning line each
a ``moveit_configs_utils`` import         refused in one line: MoveIt 2 is not on PyPI
========================================  ==========================================================

Packages are found in the workspace folders (``get_package_share_directory``,
``FindPackageShare``, xacro's ``$(find)``), a package's own folder standing for its share
folder (what colcon installs there: launch/, urdf/, worlds/).
"""

from __future__ import annotations

import shlex
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import ConfigError, NotSupportedError
from omtp_drake.ros2 import launch_api as api
from omtp_drake.scenario import Scenario
from omtp_drake.workspace import Workspace, expand_xacro_in, xacro_finds_in

#: gazebo_ros's launch files that start Gazebo (with ``world``); its package is no workspace's.
GAZEBO_LAUNCHES = ("gazebo.launch.py", "gzserver.launch.py")
#: Packages of ROS 2 itself that a launch names: not in a student's workspace, mapped to the cell.
ROS_PACKAGES = ("gazebo_ros", "robot_state_publisher")
_ROS_SHARE = Path("/opt/ros/omtp_drake")


@dataclass
class LaunchPlan:
    """What a launch file brings up, in the cell's terms."""

    file: Path
    #: The URDF text robot_state_publisher was given (None: no robot_state_publisher).
    robot_description: Optional[str] = None
    #: spawn_entity.py's: the entity's name, its source (``topic:...`` or a file) and pose.
    entity: Optional[str] = None
    spawn_source: Optional[str] = None
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)
    #: Gazebo started (gazebo.launch.py) and its world file (None: the empty world).
    gazebo: bool = False
    world: Optional[str] = None
    warnings: list[str] = field(default_factory=list)


def parse_spec(spec: str) -> tuple[str, str, dict[str, str]]:
    """``'PKG FILE.launch.py [ARG:=VALUE ...]'`` -> (package, file, arguments)."""
    words = shlex.split(spec)
    if len(words) < 2 or not words[1].endswith(".py"):
        raise ConfigError(
            f"--launch {spec!r}: give 'PKG FILE.launch.py [ARG:=VALUE ...]', as ros2 launch takes it"
        )
    bad = [w for w in words[2:] if ":=" not in w]
    if bad:
        raise ConfigError(f"--launch {spec!r}: {bad[0]!r} is no ARG:=VALUE")
    return words[0], words[1], dict(w.split(":=", 1) for w in words[2:])


def load_launch(spec: str, workspace: Sequence[str | Path]) -> LaunchPlan:
    """The plan of the launch ``spec`` with its packages in ``workspace``."""
    package, name, arguments = parse_spec(spec)
    ws = Workspace.from_dirs([Path(d) for d in workspace])
    folder = ws.package(package, needed_by="--launch")
    found = sorted(folder.rglob(name))
    if not found:
        raise ConfigError(f"--launch: package {package!r} ({folder}) has no launch file {name!r}")
    plan = LaunchPlan(found[0])
    with _ros_api(ws, found[0]):
        _run_file(found[0], dict(arguments), plan)
    return plan


@contextmanager
def _ros_api(ws: Workspace, needed_by: Path) -> Iterator[None]:
    """The ROS names a launch file imports, and where its packages are, while it runs."""

    def find(package: str) -> str:
        if package in ROS_PACKAGES:
            return str(_ROS_SHARE / package)
        return str(ws.package(package, needed_by=needed_by))

    modules = {**api.ros_modules(), "moveit_configs_utils": None}
    saved = {name: sys.modules.get(name) for name in modules}
    saved_share = api.SHARE.find, api.SHARE.expand_xacro
    sys.modules.update(modules)  # type: ignore[arg-type]
    api.SHARE.find = find
    api.SHARE.expand_xacro = lambda path, args: expand_xacro_in(ws, path, args)
    try:
        with xacro_finds_in(ws, needed_by):
            yield
    finally:
        api.SHARE.find, api.SHARE.expand_xacro = saved_share
        for name, module in saved.items():
            if module is None:
                sys.modules.pop(name, None)
            else:
                sys.modules[name] = module


def _run_file(path: Path, context: api.Context, plan: LaunchPlan) -> None:
    """Runs ``generate_launch_description()`` of the launch file and evaluates what it returns."""
    namespace: dict[str, Any] = {
        "__file__": str(path),
        "__name__": f"launch_file_{path.stem.replace('.', '_')}",
    }
    try:
        exec(compile(path.read_text(), str(path), "exec"), namespace)
        generate = namespace.get("generate_launch_description")
        if generate is None:
            raise ConfigError(f"{path}: no generate_launch_description() (a ROS 2 launch file has one)")
        description = generate()
    except ImportError as e:
        if e.name == "moveit_configs_utils":
            raise NotSupportedError(
                f"{path} builds a MoveIt 2 config (moveit_configs_utils): MoveIt 2 is not on PyPI"
            ) from None
        raise
    for entity in description.entities:
        _visit(entity, context, plan)


def _visit(entity: Any, context: api.Context, plan: LaunchPlan) -> None:
    if isinstance(entity, api.DeclareLaunchArgument):
        if entity.name not in context:
            if entity.default_value is None:
                raise ConfigError(
                    f"{plan.file}: launch argument {entity.name!r} has no value: give {entity.name}:=VALUE"
                )
            context[entity.name] = api.perform(entity.default_value, context)
        if entity.choices and context[entity.name] not in entity.choices:
            raise ConfigError(
                f"{plan.file}: {entity.name}:={context[entity.name]!r} is not one of "
                f"{', '.join(entity.choices)}"
            )
    elif isinstance(entity, api.IncludeLaunchDescription):
        _include(entity, context, plan)
    elif isinstance(entity, api.Node):
        _node(entity, context, plan)
    elif isinstance(entity, api.ExecuteProcess):
        plan.warnings.append(
            f"{plan.file}: ExecuteProcess {api.perform(entity.cmd, context)!r} is not run here"
        )
    elif isinstance(entity, (api.TimerAction, api.GroupAction)):
        for action in entity.actions:
            _visit(action, context, plan)
    elif isinstance(entity, api.RegisterEventHandler):
        actions = getattr(entity.event_handler, "on_exit", None) or []
        for action in actions if isinstance(actions, (list, tuple)) else [actions]:
            _visit(action, context, plan)
    else:
        plan.warnings.append(f"{plan.file}: {type(entity).__name__} is not supported here; left out")


def _include(entity: api.IncludeLaunchDescription, context: api.Context, plan: LaunchPlan) -> None:
    source = entity.launch_description_source
    path = Path(api.perform(getattr(source, "launch_file_path", source), context))
    arguments = entity.launch_arguments or {}
    items = arguments.items() if isinstance(arguments, dict) else arguments
    scoped = dict(context)
    scoped.update({api.perform(k, context): api.perform(v, context) for k, v in items})
    if path.parent.parent == _ROS_SHARE / "gazebo_ros" and path.name in GAZEBO_LAUNCHES:
        plan.gazebo = True
        plan.world = scoped.get("world") or None
        return
    if not path.is_file():
        raise ConfigError(f"{plan.file}: included launch file {path} does not exist")
    _run_file(path, scoped, plan)


def _node(node: api.Node, context: api.Context, plan: LaunchPlan) -> None:
    package, executable = api.perform(node.package, context), api.perform(node.executable, context)
    if (package, executable) == ("robot_state_publisher", "robot_state_publisher"):
        for parameters in node.parameters:
            if isinstance(parameters, dict) and "robot_description" in parameters:
                plan.robot_description = api.perform(parameters["robot_description"], context)
    elif (package, executable) == ("gazebo_ros", "spawn_entity.py"):
        _spawn_entity([api.perform(a, context) for a in node.arguments], plan)
    else:
        plan.warnings.append(f"{plan.file}: node {package}/{executable} is not run here")


def _spawn_entity(arguments: list[str], plan: LaunchPlan) -> None:
    """spawn_entity.py's options (the ones of a spawn from a topic or a file, and the pose)."""
    values = dict(zip(arguments[::2], arguments[1::2]))
    plan.entity = values.get("-entity")
    if plan.entity is None:
        raise ConfigError(f"{plan.file}: spawn_entity.py needs -entity NAME")
    if "-topic" in values:
        plan.spawn_source = f"topic:{values['-topic'].lstrip('/')}"
    elif "-file" in values:
        plan.spawn_source = values["-file"]
    else:
        raise ConfigError(f"{plan.file}: spawn_entity.py needs -topic TOPIC or -file FILE (valid here)")
    plan.xyz = tuple(float(values.get(k, 0.0)) for k in ("-x", "-y", "-z"))  # type: ignore[assignment]
    plan.rpy = tuple(float(values.get(k, 0.0)) for k in ("-R", "-P", "-Y"))  # type: ignore[assignment]


def plan_scenario(plan: LaunchPlan, workspace: Sequence[str | Path], folder: Path) -> Scenario:
    """The cell the plan brings up: its world (Gazebo's empty one without ``world:=``) with its
    robot spawned (a ``-topic`` robot's URDF written into ``folder`` for the loader)."""
    from omtp_drake.launch import chosen_cell
    from omtp_drake.scenario.robot_world import with_robot

    base = None
    if plan.world:
        own = chosen_cell(None, world=plan.world, workspace=workspace)
        plan.warnings += own.warnings + own.ros_only
        base = own.scenario
    if plan.entity is None:
        if base is None and not plan.gazebo:
            raise ConfigError(f"{plan.file} starts no Gazebo and spawns no robot: nothing for the cell")
        if base is None:
            from omtp_drake.scenario.robot_world import EMPTY_WORLD

            base = Scenario(name=EMPTY_WORLD, description="a ground plane")
        return base
    source = plan.spawn_source or ""
    if source.startswith("topic:"):
        if source != "topic:robot_description" or plan.robot_description is None:
            raise ConfigError(
                f"{plan.file}: spawn_entity.py -topic {source[6:]} has no robot_state_publisher "
                "robot_description to take the robot from"
            )
        robot = folder / f"{plan.entity}.urdf"
        robot.write_text(plan.robot_description)
    else:
        robot = Path(source)
    folders = [*workspace, plan.file.parent.parent]
    return with_robot(base, robot, folders, name=plan.entity, xyz=plan.xyz, rpy=plan.rpy)


@contextmanager
def launched(spec: str, workspace: Sequence[str | Path]) -> Iterator[tuple[Scenario, list[str]]]:
    """(the cell's scenario, the launch's warning lines) of ``--launch spec``, while the block
    runs (the robot's URDF lives in a temporary folder until then)."""
    import tempfile

    plan = load_launch(spec, workspace)
    with tempfile.TemporaryDirectory(prefix="omtp_launch_") as folder:
        yield plan_scenario(plan, workspace, Path(folder)), plan.warnings
