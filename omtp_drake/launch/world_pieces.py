"""The course's pieces recognised in a world's models (or a spawned SDF), as the
scenario's entries: logical cameras, the conveyor, the deletion wall; every other
model is loaded as it is (a typed model entry, :func:`~omtp_drake.launch.sdf_world.model_config`).

A model with a ROSLogicalCameraPlugin and a ``logical_camera`` sensor is a camera
named as Gazebo names the plugin's parent (the model's name in the world), at the
model's pose; a ROSConveyorBeltPlugin is the belt (the conveyor stands where its
``link`` puts it: the course's place, or where the student moved and turned it); an
ObjectDisposalPlugin is the deletion wall (where the model stands); what the student
added to those models (and to a camera's) is loaded as written
(:mod:`~omtp_drake.launch.world_additions`).
Any other plugin is one warning line; its model is loaded all the same.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from omtp_drake.assets import model_dimensions
from omtp_drake.cell.cell_models import X_W_DELETION_WALL
from omtp_drake.cell.conveyor import X_W_CONVEYOR
from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.plugins import (
    GazeboPlugin,
    camera_listing,
    camera_topic,
    check_deletion_wall,
    conveyor_power,
    conveyor_service,
    disposal_collision,
    logical_camera,
)
from omtp_drake.launch.sdf_world import World, WorldModel, model_config, sdf_pose
from omtp_drake.launch.world_additions import additions, belt_box, wall_changed
from omtp_drake.scenario import ModelConfig
from omtp_drake.workspace import Workspace

_TOL = 1e-3
#: The belt's placement tolerance (m): the course's world turns the conveyor by -1.571
#: (not -pi/2), which puts the 10 m belt's centre 1 mm off its line.
_BELT_TOL = 5e-3


@dataclass
class WorldPieces:
    cameras: list[dict] = field(default_factory=list)
    #: Camera -> its plugin's topic (``robotNamespace`` and ``image_topic_ros``).
    camera_topics: dict[str, str] = field(default_factory=dict)
    #: Camera -> what its plugin publishes (its entry of ``plugin_names.camera_listings``).
    camera_listings: dict[str, dict] = field(default_factory=dict)
    conveyor: dict | None = None
    #: The conveyor plugin's control service (its ``robot_namespace`` and ``topic``).
    conveyor_service: str | None = None
    deletion_wall: bool = False
    warnings: list[str] = field(default_factory=list)
    #: The models that are none of the course's pieces, as they are in their files.
    models: list[ModelConfig] = field(default_factory=list)
    #: Where the student moved the deletion wall (empty: the course's pose).
    deletion_wall_pose: list[float] = field(default_factory=list)
    #: The wall's model as the student wrote it, when they changed the course's wall.
    deletion_wall_model: str = ""
    #: ``link::collision`` of that model whose contacts dispose (its plugin's contact sensor's).
    deletion_wall_collision: str = ""
    #: The world's ``<gravity>`` (None: the cell's).
    gravity: list[float] | None = None


def add_world(pieces: WorldPieces, world: World, workspace: Workspace) -> None:
    """Adds the world's models (see module doc), its gravity, and what sdformat warns about;
    the world's physics step is noted once (the cell keeps its own)."""
    pieces.warnings += world.warnings
    if world.gravity is not None:
        pieces.gravity = list(world.gravity)
    if world.max_step_size is not None:
        pieces.warnings.append(
            f"{world.file}: <physics> max_step_size {world.max_step_size:g} s noted; the cell keeps its own "
            "step (plant_config.time_step)"
        )
    for model in world.models:
        add_world_model(pieces, model, workspace)


def add_world_model(pieces: WorldPieces, model: WorldModel, workspace: Workspace) -> None:
    """Adds what ``model``'s plugins make of it, or the model itself (see module doc)."""
    known = False
    for plugin in model.plugins:
        kind = plugin.kind
        if kind == "logical_camera":
            sensors = model.sensors("logical_camera")
            if len(sensors) != 1:
                raise WorkspaceError(
                    f"{plugin.where}: a logical camera model needs one logical_camera sensor"
                )
            xyz, rpy = model.pose[:3], model.pose[3:]
            camera = logical_camera(plugin, sensors[0], model.name, xyz, rpy)
            camera["housing"] = False  # (its link's visuals and collisions are loaded as written)
            pieces.cameras.append(camera)
            pieces.camera_topics[model.name] = camera_topic(plugin, model.name)
            listing, lines = camera_listing(plugin)
            pieces.warnings += lines
            if listing:
                pieces.camera_listings[model.name] = listing
        elif kind == "conveyor":
            X_WF, size = _belt_pose(model, plugin.text("link", "") or "", plugin.where)
            pieces.conveyor = {"power": conveyor_power(plugin)}
            pieces.conveyor_service = conveyor_service(plugin)
            if size:  # their belt's length and width, as written
                pieces.conveyor["belt_size"] = size
            if X_WF is not X_W_CONVEYOR:
                pose = pose_list(X_WF)
                pieces.conveyor.update(xyz=pose[:3], yaw=pose[5])
                if abs(pose[3]) > _TOL or abs(pose[4]) > _TOL:  # tilted: its parts ride the slope
                    pieces.conveyor.update(roll=pose[3], pitch=pose[4])
        elif kind == "deletion_wall":
            if _add_deletion_wall(pieces, model, plugin, workspace):
                known = True
                continue
        else:
            pieces.warnings.append(plugin.unknown_line())
            continue
        known = True
        # What the student added to it, as written, on the cell's body of the piece.
        own, lines = additions(model, kind, workspace, _piece_body(pieces, kind))
        pieces.warnings += lines
        pieces.models += [own] if own is not None else []
    if not known:
        pieces.models.append(model_config(model, workspace))


def _add_deletion_wall(
    pieces: WorldPieces, model: WorldModel, plugin: GazeboPlugin, workspace: Workspace
) -> bool:
    """The deletion wall of ``model``'s ObjectDisposalPlugin ``plugin``: where it stands,
    and what disposes (the collision its contact sensor watches). True when the wall is
    the student's model as written (they changed it, or its sensor watches nothing)."""
    check_deletion_wall(plugin)
    if _moved(model.X_WM, X_W_DELETION_WALL):
        pieces.deletion_wall_pose = pose_list(model.X_WM)
    watched = disposal_collision(plugin, model.element)
    pieces.deletion_wall = bool(watched)
    if not watched:
        pieces.warnings.append(
            f"{plugin.where}: ObjectDisposalPlugin ({plugin.name}): its contact sensor watches no single "
            'collision of the wall; as in Gazebo ("requires a single collision") it disposes of nothing'
        )
    if watched and not wall_changed(model):
        return False  # the course's wall: the catalogue's, disposing on its one box
    pieces.deletion_wall_model = model.name
    pieces.deletion_wall_collision = watched
    pieces.models.append(model_config(model, workspace))
    return True


def _piece_body(pieces: WorldPieces, kind: str | None) -> tuple[str, RigidTransform] | None:
    """The cell's body of the piece ``kind`` just added and where the cell welds it."""
    if kind == "conveyor" and pieces.conveyor is not None:
        c = pieces.conveyor
        if "xyz" not in c:
            return "conveyor_base", X_W_CONVEYOR
        return "conveyor_base", RigidTransform(
            RollPitchYaw(c.get("roll", 0.0), c.get("pitch", 0.0), c["yaw"]), c["xyz"]
        )
    if kind == "logical_camera" and pieces.cameras:
        camera = pieces.cameras[-1]
        return f"{camera['name']}_frame", RigidTransform(RollPitchYaw(camera["rpy"]), camera["xyz"])
    if kind == "deletion_wall":
        moved = pieces.deletion_wall_pose
        return "deletion_wall", RigidTransform(
            RollPitchYaw(moved[3:]), moved[:3]
        ) if moved else X_W_DELETION_WALL
    return None


def _moved(X_WA: RigidTransform, X_WC: RigidTransform, tol: float = _TOL) -> bool:
    """Whether ``X_WA`` is away from the course's ``X_WC`` (beyond ``tol``, m and rad)."""
    p_error = float(np.linalg.norm(X_WA.translation() - X_WC.translation()))
    angle = abs((X_WA.rotation().inverse() @ X_WC.rotation()).ToAngleAxis().angle())
    return p_error > tol or angle > tol


def pose_list(X: RigidTransform) -> list[float]:
    """``x y z roll pitch yaw`` of ``X`` (rounded to a nanometre, as the scenario's frames)."""
    values = [*X.translation(), *RollPitchYaw(X.rotation()).vector()]
    return [round(float(v), 9) for v in values]


def _belt_pose(model: WorldModel, link_path: str, where: str) -> tuple[RigidTransform, list[float]]:
    """``X_WF`` of the conveyor base frame the plugin's belt link (``model::nested::link``)
    puts in world: where the course has it (within 5 mm: the course's world turns the
    conveyor by -1.571, not -pi/2), or where the student moved, raised or tilted it; and
    the length and width of their belt where it is not the course's (empty: the course's).
    The belt is its ``belt_collision`` box (:func:`belt_box`) where it is one: its middle
    is F's centre line, its top the belt's."""
    names = link_path.split("::")[1:] if "::" in link_path else [link_path]
    element, X = model.element, model.X_WM
    for name in names[:-1]:
        nested = element.find(f"model[@name='{name}']")
        if nested is None:
            raise WorkspaceError(f"{where}: ROSConveyorBeltPlugin link {link_path!r}: no model {name!r}")
        element = nested
        X = X @ sdf_pose(element.findtext("pose"), where)
    link = element.find(f"link[@name='{names[-1]}']")
    if link is None:
        raise WorkspaceError(f"{where}: ROSConveyorBeltPlugin link {link_path!r} is not in the model")
    X_WL = X @ sdf_pose(link.findtext("pose"), where)
    d = model_dimensions("conveyor.urdf.xacro")
    box = belt_box(link, model.where_of(link))
    course = ((d["length"], d["width"], d["belt_thickness"]), RigidTransform())
    size, X_LG = box if box is not None else course
    # The belt's x axis is the way parts ride: F's -y (F turned a quarter from it); its
    # middle is on F's centre line, half its thickness under its top.
    X_GF = RigidTransform(RotationMatrix.MakeZRotation(np.pi / 2), [0.0, 0.0, size[2] / 2 - d["top"]])
    X_WF = X_WL @ X_LG @ X_GF
    changed = max(abs(size[0] - d["length"]), abs(size[1] - d["width"])) > _TOL
    belt = [float(size[0]), float(size[1])] if changed else []
    return (X_W_CONVEYOR if not _moved(X_WF, X_W_CONVEYOR, _BELT_TOL) else X_WF), belt
