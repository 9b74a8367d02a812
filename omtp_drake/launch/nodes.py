"""A launch's nodes, mapped to the cell.

============================================  =========================================
node (``pkg/type``)                           in the cell
============================================  =========================================
gazebo_ros/gzserver (``empty_world.launch``)  the world file's models (``world_name``)
gazebo_ros/spawn_model                        the spawned model's pieces, at ``-x -y -z
                                              -R -P -Y``, from ``-param`` or ``-file``;
                                              a model that is none of them, as it is
omtp_gazebo/conveyor_spawner_node             the spawner: its ``spawner`` parameters
                                              (rosparam), ``/start_spawn``'s remap
omtp_utilities/spawn_object_once.py           the spawner's one-part-at-a-time node
omtp_utilities/breakbeam_conveyor_stop.py     the belt stops when the beam breaks
state publishers, controller spawners,        nothing to do: the cell publishes joint
move_group, rviz, gazebo_ros/gzclient         states and tf, runs its controllers and
                                              MoveIt itself
============================================  =========================================

A Python node of the student's workspace (``omtp_utilities``' two, or their own) runs
unchanged in ros-run's session, as roslaunch would start it (its args, name, namespace
and remappings on its command line). For the commands without ROS, the course's two
helpers are the scenario's ``spawner.stop_node`` and ``conveyor.stop_on_beam``; another
Python node is a warning line there, and a node that is no Python file of the workspace
(and none of those above) is a warning line everywhere.
"""

from __future__ import annotations

import json
import math
import shlex
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.cell.conveyor import BeltGeometry
from omtp_drake.errors import ConfigError, WorkspaceError
from omtp_drake.launch.pieces import Pieces, add_urdf_model
from omtp_drake.launch.ros2_nodes import Ros2NodeProgram, find_program, ros_arguments
from omtp_drake.launch.roslaunch import Launch, Node, get_param
from omtp_drake.launch.sdf_warnings import strip_strays
from omtp_drake.launch.sdf_world import read_world, sdf_version, world_model
from omtp_drake.launch.urdf_model import UrdfModel
from omtp_drake.launch.world_pieces import WorldPieces, add_world_model
from omtp_drake.launch.world_pieces import add_world as add_world_pieces
from omtp_drake.launch.xml_lines import parse_xml
from omtp_drake.scenario import ConveyorConfig, ModelConfig
from omtp_drake.scenario.conveyor_spawner import WORLD_FRAMES, spawner_params
from omtp_drake.scenario.models import model_from_text
from omtp_drake.workspace import Workspace

#: Nodes the cell does itself (nothing to map).
CELL_NODES = {
    ("robot_state_publisher", "robot_state_publisher"),
    ("robot_state_publisher", "state_publisher"),
    ("joint_state_publisher", "joint_state_publisher"),
    ("joint_state_publisher_gui", "joint_state_publisher_gui"),
    ("controller_manager", "spawner"),
    ("controller_manager", "controller_manager"),
    ("moveit_ros_move_group", "move_group"),
    ("rviz", "rviz"),
    ("gazebo_ros", "gzclient"),
    ("tf", "static_transform_publisher"),
}
#: The course's helper nodes and the scenario flags that do their jobs without ROS.
COURSE_HELPERS = {
    ("omtp_utilities", "spawn_object_once.py"): "spawner.stop_node",
    ("omtp_utilities", "breakbeam_conveyor_stop.py"): "conveyor.stop_on_beam",
}
#: The spawner's parts count (pool) when a launch runs the conveyor spawner.
SPAWNER_POOL = 6


@dataclass
class NodeMapping:
    """What a launch's nodes make of the cell."""

    pieces: Pieces = field(default_factory=Pieces)
    world: WorldPieces = field(default_factory=WorldPieces)
    spawner: dict | None = None
    stop_node: bool = False
    stop_on_beam: bool = False
    warnings: list[str] = field(default_factory=list)
    #: The workspace's own Python nodes, for ros-run to run in its session.
    scripts: list[NodeScript] = field(default_factory=list)
    #: Nodes that run only under ros-run (a warning line for the other commands).
    ros_only: list[str] = field(default_factory=list)
    #: ROS 2 nodes that run only under ``omtp-drake ros2`` (a warning line for the others).
    ros2_only: list[str] = field(default_factory=list)
    #: The URDF models spawn_model placed so far: name -> link -> X_WL (for -reference_frame).
    placed: dict[str, dict[str, RigidTransform]] = field(default_factory=dict)


@dataclass(frozen=True)
class NodeScript:
    """A Python node of the student's workspace, as roslaunch would start it: its file and
    its command line (its args, ``__name:=``, ``__ns:=``, its remappings as ``from:=to``)."""

    path: Path
    argv: tuple[str, ...]
    #: The scenario flag (``section.key``) that does this node's job without ROS ('' for none).
    replaces: str = ""
    #: A ROS 2 node: how ``omtp-drake ros2`` starts it (None: a ROS 1 node, for ros-run).
    program: Optional[Ros2NodeProgram] = None


def _node_script(node: Node, launch: Launch, workspace: Workspace) -> NodeScript | None:
    """The node's file when it is a Python script of a workspace package (as rosrun finds it).
    Its private parameters (the launch's ``<param>``/``<rosparam>`` inside the node) go on
    its command line as ``_name:=value`` (rospy puts those under ``~`` too)."""
    folder = workspace.packages.get(node.pkg)
    if folder is not None and node.ros2:
        program = find_program(folder, node.type)
        if program is None:
            return None
        return NodeScript(program.path, ros_arguments(node, _private(launch, node)), "", program)
    if folder is None or not node.type.endswith(".py"):
        return None
    found = sorted(p for p in folder.rglob(node.type) if p.is_file())
    if not found:
        raise WorkspaceError(f"{node.where}: package {node.pkg} ({folder}) has no node {node.type}")
    argv = [*shlex.split(node.args), f"__name:={node.name.rsplit('/', 1)[-1]}"]
    if node.namespace.strip("/"):
        argv.append(f"__ns:={node.namespace}")
    argv += [f"{k}:={v}" for k, v in node.remaps.items()]
    argv += [f"_{k}:={json.dumps(v)}" for k, v in _private(launch, node).items()]
    return NodeScript(found[0], tuple(argv), COURSE_HELPERS.get((node.pkg, node.type), ""))


def _private(launch: Launch, node: Node) -> dict[str, Any]:
    """The node's private parameters (the launch's ``<param>``/``<rosparam>`` inside it)."""
    try:
        private = get_param(launch.params, node.name)
    except KeyError:
        return {}
    return private if isinstance(private, dict) else {}


def map_nodes(launch: Launch, workspace: Workspace) -> NodeMapping:
    out = NodeMapping()
    out.pieces.packages = {k: str(v) for k, v in {**workspace.models, **workspace.packages}.items()}
    for node in launch.nodes:
        key = (node.pkg, node.type)
        if key == ("gazebo_ros", "gzserver"):
            _world(out, node, workspace)
        elif key == ("gazebo_ros", "spawn_model"):
            _spawn(out, node, launch, workspace)
        elif key == ("omtp_gazebo", "conveyor_spawner_node"):
            out.spawner = _spawner(node, launch, workspace)
        elif key not in CELL_NODES:
            _other_node(out, node, launch, workspace)
    return out


def _other_node(out: NodeMapping, node: Node, launch: Launch, workspace: Workspace) -> None:
    """A node of the student's workspace: the course's two helpers also as the scenario's
    flags (for the commands without ROS); any Python node runs under ros-run; others warn."""
    script = _node_script(node, launch, workspace)
    if script is not None:
        out.scripts.append(script)
    flag = COURSE_HELPERS.get((node.pkg, node.type))
    if flag == "spawner.stop_node":
        out.stop_node = True
    elif flag == "conveyor.stop_on_beam":
        out.stop_on_beam = True
    elif script is not None and script.program is not None:
        out.ros2_only.append(
            f"{node.where}: ROS 2 node {node.pkg}/{node.type} ({node.name}) runs under omtp-drake ros2 only"
        )
    elif script is not None:
        out.ros_only.append(
            f"{node.where}: node {node.pkg}/{node.type} ({node.name}) runs under ros-run and flexbe-run only"
        )
    else:
        out.warnings.append(f"{node.where}: node {node.pkg}/{node.type} ({node.name}) is not run by the cell")


#: The world file names gzserver finds in Gazebo's own media (GAZEBO_RESOURCE_PATH) that are its
#: empty world: empty_world.launch's default ``world_name``.
GAZEBO_EMPTY_WORLDS = ("worlds/empty.world", "empty.world")


def _world(out: NodeMapping, node: Node, workspace: Workspace) -> None:
    files = [w for w in shlex.split(node.args) if not w.startswith("-")]
    if len(files) != 1:
        raise WorkspaceError(f"{node.where}: gzserver needs one world file, got args {node.args!r}")
    if files[0] in GAZEBO_EMPTY_WORLDS:
        return  # Gazebo's own empty world (its media path): the cell's floor and light, nothing more
    path = Path(files[0])
    if not path.is_absolute() or not path.is_file():
        raise WorkspaceError(
            f"{node.where}: world_name {files[0]!r} is not a world file (give $(find PKG)/...)"
        )
    add_world(out.world, path, workspace)


def add_world(pieces: WorldPieces, path: Path, workspace: Workspace) -> None:
    add_world_pieces(pieces, read_world(path, workspace), workspace)


_POSE_FLAGS = {"-x": 0, "-y": 1, "-z": 2, "-R": 3, "-P": 4, "-Y": 5}


@dataclass
class _SpawnRequest:
    """spawn_model's arguments, as gazebo_ros's spawn_model reads them."""

    kind: str = ""  # urdf or sdf
    text: str = ""
    source: str = ""  # where the description came from (for messages)
    name: str = ""
    pose: list[float] = field(default_factory=lambda: [0.0] * 6)  # x y z R P Y
    joints: dict[str, float] = field(default_factory=dict)  # -J
    options: dict[str, str] = field(default_factory=dict)  # -reference_frame, -robot_namespace
    folder: Path | None = None  # -file's folder (relative mesh paths)


def _spawn_request(node: Node, launch: Launch) -> _SpawnRequest:
    """The node's spawn_model arguments; an option spawn_model lacks, or one the cell cannot
    follow, is one WorkspaceError naming the launch file's line."""
    words, r, i = shlex.split(node.args), _SpawnRequest(), 0
    while i < len(words):
        word = words[i]
        value = words[i + 1] if i + 1 < len(words) else None
        if word in ("-urdf", "-sdf"):
            r.kind, i = word[1:], i + 1
            continue
        if word in ("-unpause", "-wait"):
            i += 1 if word == "-unpause" else 2
            continue
        if value is None:
            raise WorkspaceError(f"{node.where}: spawn_model {word} needs a value")
        if word in _POSE_FLAGS:
            r.pose[_POSE_FLAGS[word]] = _float(value, node, word)
        elif word == "-J":
            r.joints[value] = _float(words[i + 2] if i + 2 < len(words) else "", node, f"-J {value}")
            i += 1
        elif word == "-model":
            r.name = value
        elif word == "-param":
            r.source, r.text = (
                f"{node.where} (-param {node.resolve(value)})",
                _description(launch, node, value),
            )
        elif word == "-file":
            r.source, r.text, r.folder = (
                f"{node.where} (-file {value})",
                _read(Path(value), node),
                Path(value).parent,
            )
        elif word in ("-reference_frame", "-robot_namespace"):
            r.options[word] = value
        elif word not in ("-gazebo_namespace", "-database"):
            raise WorkspaceError(f"{node.where}: spawn_model option {word!r} is not supported")
        elif value not in ("", "world"):
            raise WorkspaceError(f"{node.where}: spawn_model {word} {value!r} is not supported; valid: world")
        i += 2
    if not r.kind or not r.text or not r.name:
        raise WorkspaceError(f"{node.where}: spawn_model needs -urdf or -sdf, -param or -file, and -model")
    return r


def _spawn(out: NodeMapping, node: Node, launch: Launch, workspace: Workspace) -> None:
    """A spawn_model node: the course's pieces recognised in its model, any other model
    loaded as it is, where spawn_model puts it."""
    r = _spawn_request(node, launch)
    # spawn_model's -robot_namespace defaults to the node's namespace (rospy.get_namespace()).
    text = with_robot_namespace(r.text, r.options.get("-robot_namespace", node.namespace))
    X_WR = _reference(out, node, r.options.get("-reference_frame", ""))
    if X_WR is None:
        return
    X_WM = X_WR @ RigidTransform(RollPitchYaw(r.pose[3:]), r.pose[:3])
    pose = [*X_WM.translation(), *RollPitchYaw(X_WM.rotation()).vector()]  # in world
    if r.kind == "urdf":
        urdf = UrdfModel.from_text(text, r.source)
        if not add_urdf_model(out.pieces, urdf, X_WM, r.source, r.joints, r.name):
            out.world.models.append(_own_model(text, r.source, workspace, r.name, pose))
        while out.pieces.own:  # what the student wrote beside and in the course's pieces
            own = out.pieces.own.pop(0)
            entry = _own_model(own.text, own.where, workspace, own.name, own.pose, static=own.static)
            entry.open_links = list(own.open_links)
            entry.parent = own.parent  # (a link of the cell's arm or gripper: it hangs there)
            out.world.models.append(entry)
        out.placed[r.name] = {link: X_WM @ X_ML for link, X_ML in urdf.link_poses(r.joints).items()}
        return
    doc = parse_xml(Path(r.source), text)
    model = doc.root.find("model")
    if model is None:
        raise WorkspaceError(f"{r.source}: has no <model>")
    out.warnings += strip_strays(doc, model)
    spawned = world_model(
        r.name, tuple(pose), model, r.source, version=sdf_version(doc), folder=r.folder, doc=doc
    )
    add_world_model(out.world, spawned, workspace)


def _own_model(
    text: str, source: str, workspace: Workspace, name: str, pose: list[float], *, static: bool = False
) -> ModelConfig:
    """A spawned URDF that is none of the course's pieces, as it is (its own geometry,
    joints, inertia), where spawn_model puts it."""
    xyz, rpy = tuple(pose[:3]), tuple(pose[3:])
    try:
        return model_from_text(text, source, workspace, name=name, xyz=xyz, rpy=rpy, static=static)  # type: ignore[arg-type]
    except ConfigError as e:
        if isinstance(e, WorkspaceError):
            raise
        raise WorkspaceError(str(e)) from None


def _reference(out: NodeMapping, node: Node, frame: str) -> RigidTransform | None:
    """``X_WR`` of spawn_model's ``-reference_frame`` as Gazebo's SpawnModel finds it (the
    world; a model spawned before in the launch, at its root link; its ``model::link``);
    None, with the warning line of Gazebo's failed spawn, for any other name."""
    if frame in WORLD_FRAMES:
        return RigidTransform()
    model, _, link = frame.partition("::")
    links = out.placed.get(model, {})
    if links and (link in links or not link):
        return links[link] if link else next(iter(links.values()))
    out.warnings.append(
        f"{node.where}: spawn_model -reference_frame {frame!r}: SpawnModel: reference frame not found "
        f"(models spawned before it: {', '.join(out.placed) or 'none'}); the model is not spawned"
    )
    return None


def with_robot_namespace(text: str, namespace: str) -> str:
    """The model's XML with ``<robotNamespace>`` in every ``<plugin>`` that has none, as
    Gazebo's SpawnModel adds the request's ``robot_namespace`` (nothing for the root)."""
    if not namespace.strip("/") or "<plugin" not in text:
        return text
    root = ET.fromstring(text.strip())
    changed = False
    for plugin in root.iter("plugin"):
        if plugin.find("robotNamespace") is None:
            ET.SubElement(plugin, "robotNamespace").text = namespace
            changed = True
    return ET.tostring(root, encoding="unicode") if changed else text


def _float(text: str, node: Node, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise WorkspaceError(f"{node.where}: spawn_model {what} {text!r} is not a number")
    return value


def _read(path: Path, node: Node) -> str:
    if not path.is_file():
        raise WorkspaceError(f"{node.where}: spawn_model -file {path}: no such file")
    return path.read_text()


def _description(launch: Launch, node: Node, name: str) -> str:
    full = node.resolve(name)
    try:
        value = get_param(launch.params, full)
    except KeyError:
        raise WorkspaceError(f"{node.where}: spawn_model -param {full}: no such parameter is set") from None
    if not isinstance(value, str):
        raise WorkspaceError(f"{node.where}: spawn_model -param {full} is not a text")
    return value


def _spawner(node: Node, launch: Launch, workspace: Workspace) -> dict:
    """The scenario's spawner of the course's conveyor_spawner_node's ``spawner`` params
    (read by :func:`omtp_drake.scenario.conveyor_spawner.spawner_params`)."""
    try:
        config: Any = get_param(launch.params, node.resolve("~spawner"))
    except KeyError:
        raise WorkspaceError(f"{node.where}: conveyor_spawner_node has no ~spawner parameters") from None
    where = f"{node.where} (~spawner)"
    try:
        spawner = spawner_params(config, where, lambda uri: _mesh_file(uri, workspace))
    except ConfigError as e:
        raise WorkspaceError(str(e)) from None
    spawner["xyz"] = spawner["objects"][0]["xyz"]
    spawner["start_service"] = node.remaps.get("/start_spawn", "/start_spawn")
    return spawner


def _mesh_file(uri: str, workspace: Workspace) -> str:
    """The file of a ``package://PKG/...`` mesh in the workspace ("" when none has it)."""
    if not uri.startswith("package://"):
        return ""
    package, _, rest = uri[len("package://") :].partition("/")
    folder = workspace.packages.get(package)
    path = Path(folder) / rest if folder is not None else None
    return str(path) if path is not None and path.is_file() else ""


def rest_standins_on_belt(spawner: dict, conveyor: dict | None, part_size: float = 0.2) -> None:
    """The course's box stands in for a spawner object whose mesh nobody has: one spawned
    over the belt as loaded (``conveyor``: the scenario's section; moved, raised or tilted),
    at most two parts' size above it, starts resting on it (as the built-in scenarios place
    the course's spawn points). Without a conveyor, or in another reference frame, the
    object's pose stays as its file gives it."""
    if conveyor is None or spawner["reference_frame"] not in WORLD_FRAMES:
        return
    keys = ("xyz", "yaw", "roll", "pitch", "belt_size")
    belt = BeltGeometry.of(ConveyorConfig(**{k: v for k, v in conveyor.items() if k in keys}))
    for item in spawner["objects"]:
        p_W = np.array(item["xyz"], dtype=float)
        if item["mesh_file"] or not belt.over(p_W) or belt.height(p_W) > 2 * part_size:
            continue
        # A cube's reach from its centre along the belt's normal, at the object's orientation.
        R_WO = RollPitchYaw(item["rpy"]).ToRotationMatrix().matrix()
        support = 0.5 * part_size * float(np.abs(R_WO.T @ belt.normal).sum())
        item["xyz"] = [round(float(v), 6) for v in belt.resting_point(p_W, support)]
    spawner["xyz"] = spawner["objects"][0]["xyz"]
