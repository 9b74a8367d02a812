"""A student's own cell: their launch file or world, in their workspace, as a ``Scenario``.

:func:`own_cell` is the one door from the options ``--launch 'PKG FILE.launch
[ARG:=VALUE ...]'``, ``--world FILE.world`` and ``--workspace DIR`` (and
``Cell(launch=..., workspace=...)``) to the typed scenario the station builds: the
launch is read as roslaunch reads it (:mod:`~omtp_drake.launch.roslaunch`), its nodes
mapped to the cell (:mod:`~omtp_drake.launch.nodes`), and the pieces found become the
scenario's robots, cameras, bins, belt, beam, wall and spawner, at the poses the files
give; every other model the world or a ``spawn_model`` loads is the scenario's model entry,
as it is in its file. What the cell does not take is one :class:`~omtp_drake.errors.WorkspaceError`
(nothing is built); what it leaves out, and what sdformat and roslaunch warn about, is a
warning line in ``OwnCell.warnings``.
"""

from __future__ import annotations

import copy
import dataclasses
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from omtp_drake.errors import ConfigError, WorkspaceError
from omtp_drake.launch.standins import standin_dirs
from omtp_drake.workspace import Workspace

if TYPE_CHECKING:
    from pydrake.math import RigidTransform

    from omtp_drake.launch.nodes import NodeMapping, NodeScript
    from omtp_drake.launch.urdf_model import UrdfModel
    from omtp_drake.scenario import Scenario

# The launch and world readers (and Drake) are imported by the functions that read a student's
# files: a scenario's cell is an ``OwnCell`` too (``launch.options.cell_of``), and a command run
# on a scenario reads no launch file.


@dataclass
class OwnCell:
    """The scenario of a student's files, what was left out, and their MoveIt config."""

    scenario: Scenario
    warnings: list[str] = field(default_factory=list)
    #: The MoveIt config package the launch's ``move_group.launch`` belongs to (None: the cell's).
    moveit_config: Path | None = None
    #: The spawned URDF models and their placements in world.
    models: list[tuple[UrdfModel, RigidTransform]] = field(default_factory=list)
    #: The scenario as plain data (what ``scenario_from_dict`` typed and checked).
    document: dict = field(default_factory=dict)
    #: The workspace's Python nodes the launch starts (ros-run runs them in its session).
    nodes: list[NodeScript] = field(default_factory=list)
    #: The lines to warn with where the nodes do not run (the commands without ROS).
    ros_only: list[str] = field(default_factory=list)
    #: The ros2_control controllers a ROS 2 launch's spawners activate (for the ros2_control layer).
    controllers: list[str] = field(default_factory=list)
    #: The lines to warn with where the workspace's ROS 2 nodes do not run (all but ``ros2``).
    ros2_only: list[str] = field(default_factory=list)

    def write(self, folder: str | os.PathLike, *, with_nodes: bool = False) -> Path:
        """The scenario as a YAML file in ``folder`` (for the commands that take a file).
        ``with_nodes``: for a run that runs :attr:`nodes` themselves, so the scenario flags
        that stand in for them are off."""
        from omtp_drake.scenario import scenario_text

        path = Path(folder) / f"{self.scenario.name or 'own_cell'}.yaml"
        path.write_text(scenario_text(self.document_for(with_nodes=with_nodes)))
        return path

    def document_for(self, *, with_nodes: bool = False) -> dict:
        """:attr:`document`; ``with_nodes``: with the flags that stand in for :attr:`nodes` off."""
        document = copy.deepcopy(self.document)
        for node in self.nodes if with_nodes else ():
            if node.replaces:
                section, key = node.replaces.split(".")
                document[section][key] = False
        return document

    def frames(self, positions: Mapping[str, float] | None = None) -> dict[str, RigidTransform]:
        """``X_WL`` of every link of the spawned URDF models, as their files place them, at
        joint ``positions`` (joint name -> value; 0 for the others)."""
        out: dict[str, RigidTransform] = {}
        for model, X_WM in self.models:
            for link, X_ML in model.link_poses(positions).items():
                if link != "world":  # Gazebo's name for the world itself: the model is welded to it
                    out.setdefault(link, X_WM @ X_ML)
        return out


def student_workspace(
    dirs: Sequence[str | os.PathLike] = (), environ: Mapping[str, str] | None = None
) -> Workspace:
    """The workspace of ``dirs`` (``--workspace``), ``ROS_PACKAGE_PATH``, ``GAZEBO_MODEL_PATH``
    and the project's stand-ins (last: a student's own package wins)."""
    return Workspace.from_dirs(dirs, environ=environ, bundled=standin_dirs())


def own_cell(
    launch: str | None = None,
    world: str | os.PathLike | None = None,
    workspace: Sequence[str | os.PathLike] | str | os.PathLike = (),
    *,
    environ: Mapping[str, str] | None = None,
) -> OwnCell:
    """The cell of ``launch`` (``'PKG FILE.launch [ARG:=VALUE ...]'``) or ``world`` (a
    ``.world`` file) in ``workspace`` (folders); see module doc."""
    from omtp_drake.launch.nodes import NodeMapping, add_world
    from omtp_drake.launch.pieces import merge_pedestals
    from omtp_drake.scenario import FrameConfig, scenario_from_dict

    if (launch is None) == (world is None):
        raise WorkspaceError("give one of --launch 'PKG FILE.launch [ARG:=VALUE ...]' or --world FILE.world")
    dirs = [workspace] if isinstance(workspace, (str, os.PathLike)) else list(workspace)
    if world is not None:  # the package holding the world too (its models, as a sourced workspace has)
        dirs += [f for f in Path(world).expanduser().resolve().parents if (f / "package.xml").is_file()][:1]
    ws = student_workspace(dirs, environ)
    moveit: Path | None = None
    controllers: list[str] = []
    if launch is not None:
        mapping, controllers, moveit, source = _mapped_launch(launch, ws, environ)
    else:
        mapping, source = NodeMapping(), Path(world).expanduser().resolve()  # type: ignore[arg-type]
        add_world(mapping.world, source, ws)
    name = source.stem
    merge_pedestals(mapping.pieces)
    document = _document(mapping, name, f"{launch or source} (a student's own files)")
    try:
        # (the loader's models and fixed links are typed already: most of the document's
        # text, which Drake's pure-Python YAML reader would otherwise read back)
        scenario = scenario_from_dict(
            {**document, "models": [], "frames": []},
            source=str(source),
            name=name,
            models=mapping.world.models,
            frames=[FrameConfig(**frame) for frame in document["frames"]],
        )
    except ConfigError as e:
        if isinstance(e, WorkspaceError):
            raise
        raise WorkspaceError(f"{source}: {e}") from None
    warnings = mapping.pieces.warnings + mapping.world.warnings + mapping.warnings
    return OwnCell(
        scenario,
        warnings,
        moveit,
        mapping.pieces.models,
        document,
        mapping.scripts,
        mapping.ros_only,
        controllers,
        mapping.ros2_only,
    )


def _mapped_launch(
    launch: str, ws: Workspace, environ: Mapping[str, str] | None
) -> tuple[NodeMapping, list[str], Path | None, Path]:
    """What the launch ``launch`` starts, mapped onto the cell (its models' controllers
    started as its spawners start them), the controllers it names, its MoveIt config and
    its file."""
    from omtp_drake.launch.controller_spawners import activate_ros2_controllers, start_spawned_controllers
    from omtp_drake.launch.launch_py import read_launch_file
    from omtp_drake.launch.nodes import map_nodes
    from omtp_drake.launch.roslaunch import find_launch_file, parse_launch_spec

    pkg, file, args = parse_launch_spec(launch)
    path = find_launch_file(ws, pkg, file)
    read = read_launch_file(path, args, ws, environ)
    mapping = map_nodes(read, ws)
    mapping.warnings[:0] = read.warnings
    # controller_manager's spawners start the controllers of the models loaded as they are
    # (the course's arms' spawners: the cell drives its arms itself).
    mapping.world.models[:] = start_spawned_controllers(
        mapping.world.models, read, cell_namespaces=[robot["name"] for robot in mapping.pieces.robots]
    )
    models = mapping.world.models
    models[:], lines = activate_ros2_controllers(models, read.controllers, str(path))
    mapping.warnings += lines
    return mapping, read.controllers, read.moveit_config, path


def _frame(name: str, X_WL: RigidTransform) -> dict:
    """An extra frame of the scenario: a link fixed to the world where its file puts it."""
    from pydrake.math import RollPitchYaw

    xyz = [round(float(v), 9) for v in X_WL.translation()]
    rpy = [round(float(v), 9) for v in RollPitchYaw(X_WL.rotation()).vector()]
    return {"name": name, "parent": "world", "xyz": xyz, "rpy": rpy}


def _plugin_names(mapping: NodeMapping) -> dict:
    """The plugins' names the files set, where they differ from the course's."""
    from omtp_drake.scenario.plugin_names import CameraListing, GripperNames, PluginNames

    pieces, world = mapping.pieces, mapping.world
    names = PluginNames(
        grippers=[GripperNames(**g) for g in pieces.plugin_names["grippers"]],
        camera_topics=dict(world.camera_topics),
        camera_listings={c: CameraListing(**v) for c, v in world.camera_listings.items()},
        **{k: v for k, v in pieces.plugin_names.items() if k != "grippers"},
    )
    if world.conveyor_service is not None:
        names.conveyor_control_service = world.conveyor_service
    return names.without_defaults({r["name"]: r.get("gripper", "") for r in pieces.robots})


def _document(mapping: NodeMapping, name: str, description: str) -> dict:
    """The scenario document of what the nodes made of the cell."""
    from omtp_drake.launch.nodes import SPAWNER_POOL, rest_standins_on_belt

    pieces, world = mapping.pieces, mapping.world
    document: dict = {
        "name": name,
        "description": description,
        "robots": pieces.robots,
        "cameras": world.cameras,
        "bins": pieces.bins,
        "break_beam": pieces.break_beam,
        "deletion_wall": world.deletion_wall,
        "frames": [_frame(name, X_WL) for name, X_WL in pieces.frames.items()],
    }
    if world.models:
        document["models"] = [dataclasses.asdict(model) for model in world.models]
    if world.gravity is not None:
        document["gravity"] = world.gravity
    if pieces.break_beam_pose:
        document["break_beam_pose"] = pieces.break_beam_pose
    if world.deletion_wall_pose:
        document["deletion_wall_pose"] = world.deletion_wall_pose
    if world.deletion_wall_model:
        document["deletion_wall_model"] = world.deletion_wall_model
    if world.deletion_wall_collision:
        document["deletion_wall_collision"] = world.deletion_wall_collision
    if world.conveyor is not None:
        document["conveyor"] = {**world.conveyor, "stop_on_beam": mapping.stop_on_beam}
    elif mapping.stop_on_beam:
        raise WorkspaceError("breakbeam_conveyor_stop.py runs but the world has no conveyor")
    names = _plugin_names(mapping)
    if names:
        document["plugin_names"] = names
    if pieces.suction_checks is not None:
        document["suction"] = {"consecutive_checks": pieces.suction_checks}
    if mapping.spawner is not None:
        # spawn_object_once.py is the course's one-part-at-a-time rule.
        one_at_a_time = mapping.stop_node
        rest_standins_on_belt(mapping.spawner, document.get("conveyor"))
        document["spawner"] = {
            **mapping.spawner,
            "stop_node": mapping.stop_node,
            "one_at_a_time": one_at_a_time,
        }
        document["part_pool"] = SPAWNER_POOL
    elif mapping.stop_node:
        mapping.warnings.append(
            "spawn_object_once.py runs but no conveyor_spawner_node does; nothing to stop"
        )
    return document
