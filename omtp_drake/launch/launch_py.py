"""ROS 2's Python launch files (``.launch.py``), read as ``ros2 launch`` runs them.

:func:`read_launch_py` runs the file's ``generate_launch_description()`` with the project's
own ``launch`` and ``launch_ros`` (``shims/``: the API a course or tutorial file uses; neither
is on PyPI) first on ``sys.path``, and ``AMENT_PREFIX_PATH`` at the workspace's ament prefix
(so ``get_package_share_directory`` and ``FindPackageShare`` find its packages), both only
while the file runs. Its entities are visited as the launch service visits them (arguments,
substitutions, conditions, includes, groups, timers, event handlers); what would start is
recorded, not started, and given as the :class:`~omtp_drake.launch.roslaunch.Launch` the
ROS 1 reader gives, its nodes mapped to the cell by :mod:`~omtp_drake.launch.nodes`:

=======================================  ==============================================
started                                  in the cell
=======================================  ==============================================
``robot_state_publisher``                its ``robot_description``: on the topic it
                                         publishes (``/robot_description``)
gazebo_ros ``gazebo.launch.py`` (its     the ``world:=`` file's models (none: the empty
``gzserver``)                            world)
gazebo_ros ``spawn_entity.py``           ``spawn_model`` of ``-topic``/``-file``,
                                         ``-entity``, ``-x -y -z -R -P -Y``
controller_manager ``spawner``,          the controllers it activates
``ros2 control load_controller``         (``Launch.controllers``)
``joint_state_publisher_gui``,           one info line: the cell does it itself
``rviz2``, ``gzclient``
a Python node of the workspace           started by ``omtp-drake ros2`` as ``ros2 launch``
                                         would (:mod:`~omtp_drake.launch.ros2_nodes`)
any other node or process                one warning line: not run by the cell
=======================================  ==============================================

A launch that imports ``moveit_configs_utils`` is refused with one line (MoveIt 2 is not on PyPI).
"""

from __future__ import annotations

import ast
import importlib.util
import logging
import shlex
import sys
import traceback
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import yaml

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.roslaunch import Launch, Node, get_param, join_name, put_param, read_launch
from omtp_drake.workspace import Workspace, expand_xacro_in
from omtp_drake.workspace.xacro_files import AMENT_PREFIX_PATH, ament_prefix, environment_set

_log = logging.getLogger("omtp_drake")

#: The folder of the project's ``launch`` and ``launch_ros`` packages.
SHIM_DIR = Path(__file__).resolve().parent / "shims"
_SHIMMED = ("launch", "launch_ros")
#: Processes that end by themselves (``OnProcessExit`` of them runs its actions).
_ONE_SHOT = {
    ("gazebo_ros", "spawn_entity.py"),
    ("controller_manager", "spawner"),
    ("controller_manager", "spawner.py"),
}
_SPAWNERS = {"spawner", "spawner.py"}
#: Nodes the cell does itself: what to say about each.
_CELL_DOES = {
    "joint_state_publisher_gui": "the cell's joint sliders are omtp-drake view's",
    "joint_state_publisher": "the cell publishes /joint_states itself",
    "rviz2": "omtp-drake shows the cell in Meshcat (view, run --meshcat)",
}


def read_launch_py(
    path: Path, args: Mapping[str, str], workspace: Workspace, environ: Mapping[str, str] | None = None
) -> Launch:
    """What the launch file ``path`` run with ``args`` (``ARG:=VALUE``) starts (see module doc)."""
    launch = Launch(file=path)
    with _api(), environment_set(AMENT_PREFIX_PATH, str(ament_prefix(workspace))):
        from launch.launch_context import LaunchContext

        context = LaunchContext(launch_configurations=dict(args))
        context.load_file = lambda file: _load(Path(file), launch)
        context.run_command = lambda words, text: _command(words, text, workspace)
        context.files.append(str(path.resolve()))
        try:
            context.visit(_load(path, launch))
            _fire_handlers(context)
        except WorkspaceError:
            raise
        except Exception as e:
            raise WorkspaceError(f"{_where(e, launch)}: {type(e).__name__}: {e}") from None
    _started(launch, context.started, workspace)
    return launch


@contextmanager
def _api() -> Iterator[None]:
    """The project's ``launch`` and ``launch_ros`` first on ``sys.path`` (a real install's
    modules set aside, and put back after)."""
    saved = {k: sys.modules.pop(k) for k in list(sys.modules) if k.split(".")[0] in _SHIMMED}
    sys.path.insert(0, str(SHIM_DIR))
    try:
        yield
    finally:
        sys.path.remove(str(SHIM_DIR))
        for name in [k for k in sys.modules if k.split(".")[0] in _SHIMMED]:
            del sys.modules[name]
        sys.modules.update(saved)


def _load(path: Path, launch: Launch) -> Any:
    """The launch description of the file ``path`` (its ``generate_launch_description()``)."""
    if not path.is_file():
        raise WorkspaceError(
            f"{launch.files[-1] if launch.files else path}: launch file {path} does not exist"
        )
    path = path.resolve()  # the package's own folder, not the ament prefix's link to it
    _refuse_moveit(path)
    launch.files.append(path)
    spec = importlib.util.spec_from_file_location(f"_omtp_launch_{len(launch.files)}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    generate = getattr(module, "generate_launch_description", None)
    if generate is None:
        raise WorkspaceError(f"{path}: has no generate_launch_description() (not a ROS 2 launch file)")
    return generate()


def _refuse_moveit(path: Path) -> None:
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if not isinstance(node, (ast.Import, ast.ImportFrom)):
            continue
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
        if any(name.split(".")[0] == "moveit_configs_utils" for name in names):
            raise WorkspaceError(
                f"{path}:{node.lineno}: imports moveit_configs_utils: a launch that builds a MoveIt 2 "
                "config is not supported (MoveIt 2 is not on PyPI; the cell plans itself, see docs/ros2.md)"
            )


def _where(error: Exception, launch: Launch) -> str:
    """``file:line`` of the launch file's line the error came from (its last frame in one)."""
    files = {str(f) for f in launch.files}
    frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename in files]
    return f"{frames[-1].filename}:{frames[-1].lineno}" if frames else str(launch.file)


def _command(words: list[str], text: str, workspace: Workspace) -> str:
    """The output of a ``Command`` substitution: xacro only (run in the workspace)."""
    if not words or Path(words[0]).name not in ("xacro", "xacro.py"):
        raise WorkspaceError(f"Command {text!r} is not supported; valid: xacro FILE [NAME:=VALUE ...]")
    files = [w for w in words[1:] if ":=" not in w and not w.startswith("-")]
    if len(files) != 1 or not Path(files[0]).is_file():
        raise WorkspaceError(f"Command {text!r}: xacro needs one existing file")
    mappings = dict(w.split(":=", 1) for w in words[1:] if ":=" in w)
    return expand_xacro_in(workspace, Path(files[0]).resolve(), mappings)


def _fire_handlers(context: Any) -> None:
    """Runs each event handler's actions once its process has started (``OnProcessStart``)
    or, for a process that ends by itself (a spawner), ended (``OnProcessExit``)."""
    fired: set[int] = set()
    changed = True
    while changed:
        changed = False
        for handler in list(context.handlers):
            target = handler.target_action
            started = [s for s in context.started if target is None or s.action is target]
            on_exit = type(handler).__name__ == "OnProcessExit"
            if id(handler) in fired or not started or (on_exit and not all(map(_one_shot, started))):
                continue
            fired.add(id(handler))
            changed = True
            actions = handler.actions
            if callable(actions) and not hasattr(actions, "visit"):
                actions = actions(None, context)
            for action in actions if isinstance(actions, (list, tuple)) else [actions]:
                context.visit(action)


def _one_shot(started: Any) -> bool:
    cmd = started.cmd
    return (started.package, started.executable) in _ONE_SHOT or cmd[:2] == ["ros2", "control"]


def _started(launch: Launch, started: list[Any], workspace: Workspace) -> None:
    """Puts what started into ``launch`` (params, nodes, controllers, warnings)."""
    for s in started:  # descriptions first: a spawn may name a topic published later
        if (s.package, s.executable) == ("robot_state_publisher", "robot_state_publisher"):
            _state_publisher(launch, s)
    for s in started:
        if s.package:
            _node(launch, s, workspace)
        else:
            _process(launch, s, workspace)


def _node_name(s: Any) -> str:
    return join_name(s.namespace, s.name or Path(s.executable).stem)


def _params(s: Any) -> dict[str, Any]:
    """The node's parameters: its dicts, and its YAML files' entries for it (``/**`` too)."""
    out: dict[str, Any] = {}
    full = _node_name(s)
    for item in s.parameters:
        if isinstance(item, dict):
            out.update(item)
            continue
        path = Path(item)
        if not path.is_file():
            raise WorkspaceError(f"{s.where}: parameter file {path} does not exist")
        data = yaml.safe_load(path.read_text()) or {}
        for key, section in data.items() if isinstance(data, dict) else ():
            if key in ("/**", full, full.lstrip("/"), Path(full).name) and isinstance(section, dict):
                out.update(section.get("ros__parameters", {}))
    return out


def _state_publisher(launch: Launch, s: Any) -> None:
    params = _params(s)
    description = params.get("robot_description")
    if not isinstance(description, str):
        raise WorkspaceError(
            f"{s.where}: robot_state_publisher has no robot_description parameter (a URDF text)"
        )
    remaps: dict[str, str] = dict(s.remappings)
    topic = join_name(
        s.namespace, remaps.get("robot_description", remaps.get("/robot_description", "robot_description"))
    )
    put_param(launch.params, topic, description)


def _node(launch: Launch, s: Any, workspace: Workspace) -> None:
    key, full = (s.package, s.executable), _node_name(s)
    for name, value in _params(s).items():
        put_param(launch.params, f"{full}/{name}", value)
    args = s.cmd[1:]
    if key == ("robot_state_publisher", "robot_state_publisher"):
        return
    if key == ("gazebo_ros", "spawn_entity.py"):
        words = _spawn_model_args(launch, s, args)
        launch.nodes.append(
            Node("gazebo_ros", "spawn_model", full, s.namespace, shlex.join(words), {}, s.where)
        )
    elif s.package == "controller_manager" and s.executable in _SPAWNERS:
        _spawner(launch, s, args)
    elif s.package in _CELL_DOES or s.package == "rviz2":
        _log.info("%s: node %s/%s: %s", s.where, s.package, s.executable, _CELL_DOES[s.package])
    elif s.package in workspace.packages:  # the workspace's own: mapped (and started) as ROS 2 nodes
        remaps = dict(s.remappings)
        launch.nodes.append(
            Node(s.package, s.executable, full, s.namespace, shlex.join(args), remaps, s.where, True)
        )
    else:
        launch.warnings.append(f"{s.where}: node {s.package}/{s.executable} ({full}) is not run by the cell")


#: spawn_entity.py's options that take a value and are passed on as they are.
_SPAWN_PASSED = {"-x", "-y", "-z", "-R", "-P", "-Y", "-reference_frame", "-robot_namespace"}
#: spawn_entity.py's options that do not change what is spawned (with a value / flags).
_SPAWN_IGNORED = {"-timeout", "-spawn_service_timeout", "-gazebo_namespace"}
_SPAWN_FLAGS = {"-unpause", "-wait", "-package_to_model", "-b", "-bond"}


def _spawn_model_args(launch: Launch, s: Any, args: list[str]) -> list[str]:
    """spawn_entity.py's arguments as ROS 1 spawn_model's (``-topic`` as ``-param``: the
    description a robot_state_publisher of the launch publishes there)."""
    out: list[str] = []
    text = ""
    i = 0
    while i < len(args):
        word, value = args[i], args[i + 1] if i + 1 < len(args) else ""
        if word in _SPAWN_FLAGS:
            i += 1
            continue
        if word == "-topic":
            topic = join_name(s.namespace, value)
            try:
                text = get_param(launch.params, topic)
            except KeyError:
                raise WorkspaceError(
                    f"{s.where}: spawn_entity.py -topic {value}: no robot_state_publisher of the launch "
                    f"publishes {topic}"
                ) from None
            if not isinstance(text, str):
                raise WorkspaceError(
                    f"{s.where}: spawn_entity.py -topic {value}: {topic} is no description text"
                )
            out += ["-param", topic]
        elif word == "-file":
            if not Path(value).is_file():
                raise WorkspaceError(f"{s.where}: spawn_entity.py -file {value}: no such file")
            text = Path(value).read_text()
            out += ["-file", value]
        elif word == "-entity":
            out += ["-model", value]
        elif word in _SPAWN_PASSED:
            out += [word, value]
        elif word not in _SPAWN_IGNORED:
            raise WorkspaceError(
                f"{s.where}: spawn_entity.py option {word!r} is not supported; valid: -topic, -file, "
                f"-entity, {', '.join(sorted(_SPAWN_PASSED | _SPAWN_IGNORED | _SPAWN_FLAGS))}"
            )
        i += 2
    if not text or "-model" not in out:
        raise WorkspaceError(f"{s.where}: spawn_entity.py needs -topic or -file, and -entity")
    return [f"-{_kind(text)}", *out]


def _kind(text: str) -> str:
    """``urdf`` or ``sdf``: the description's kind, as spawn_entity.py tells them apart."""
    try:
        return "sdf" if ET.fromstring(text.strip()).tag == "sdf" else "urdf"
    except ET.ParseError:
        return "urdf"


#: controller_manager's spawner options that take a value.
_SPAWNER_VALUED = {
    "-c", "--controller-manager", "-p", "--param-file", "-n", "--namespace", "-t", "--controller-type",
    "--controller-manager-timeout", "--switch-timeout", "--service-call-timeout", "--controller-ros-args",
}  # fmt: skip
_INACTIVE = {"--inactive", "--stopped", "--load-only"}


def _spawner(launch: Launch, s: Any, args: list[str]) -> None:
    """The controllers a spawner activates (``--inactive`` ones: loaded, not active)."""
    names: list[str] = []
    i = 0
    while i < len(args):
        names += [] if args[i].startswith("-") else [args[i]]
        i += 2 if args[i] in _SPAWNER_VALUED else 1
    if _INACTIVE & set(args):
        _log.info("%s: controllers %s are loaded inactive", s.where, ", ".join(names))
        return
    launch.controllers += [n for n in names if n not in launch.controllers]


def _process(launch: Launch, s: Any, workspace: Workspace) -> None:
    """An ``ExecuteProcess``: gzserver (the world), gzclient, ``ros2 run`` and ``ros2 control``."""
    cmd = s.cmd
    program = Path(cmd[0]).name if cmd else ""
    if program == "gzserver":
        world = _gz_world(cmd[1:])
        if world:
            path = Path(world).expanduser().resolve()
            if not path.is_file():
                raise WorkspaceError(f"{s.where}: gzserver world {world!r}: no such file")
            launch.nodes.append(Node("gazebo_ros", "gzserver", "/gazebo", "/", str(path), {}, s.where))
    elif program == "gzclient":
        _log.info("%s: gzclient: omtp-drake shows the cell in Meshcat (view, run --meshcat)", s.where)
    elif cmd[:2] == ["ros2", "run"] and len(cmd) >= 4:
        s.package, s.executable, s.cmd = cmd[2], cmd[3], cmd[3:]
        _node(launch, s, workspace)
    elif cmd[:3] == ["ros2", "control", "load_controller"] or cmd[:3] == [
        "ros2",
        "control",
        "load_start_controller",
    ]:
        words = [w for w in cmd[3:] if not w.startswith("-") and w not in ("active", "start", "inactive")]
        active = cmd[2] == "load_start_controller" or any(w in ("active", "start") for w in cmd[3:])
        if active:
            launch.controllers += [n for n in words if n not in launch.controllers]
    else:
        launch.warnings.append(f"{s.where}: process {shlex.join(cmd)!r} is not run by the cell")


#: gzserver's options that take a value.
_GZ_VALUED = {
    "-s",
    "--server-plugin",
    "-e",
    "--physics",
    "--record_path",
    "--seed",
    "--iters",
    "-p",
    "--play",
}


def _gz_world(words: list[str]) -> str:
    """The world file of gzserver's command line ('' for none: Gazebo's empty world)."""
    i = 0
    while i < len(words):
        if words[i] in _GZ_VALUED:
            i += 2
            continue
        if words[i] and not words[i].startswith("-"):
            return words[i]
        i += 1
    return ""


def read_launch_file(
    path: Path, args: Mapping[str, str], workspace: Workspace, environ: Mapping[str, str] | None = None
) -> Launch:
    """The launch file ``path`` read as its kind is: ``.py`` as ``ros2 launch``, else roslaunch's XML."""
    if path.suffix == ".py":
        return read_launch_py(path, args, workspace, environ)
    return read_launch(path, args, workspace, environ)
