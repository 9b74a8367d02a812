"""The cell's models in a plant: every model of a scenario, welded at its pose.

:func:`add_cell_models` adds the floor, pedestals and arms with grippers, bins,
conveyor, break beam, deletion wall, camera frames and the parts to a plant that
is not finalized, and returns their instances (:class:`CellModels`). The station
(:func:`omtp_drake.cell.station.build_station`) builds on it, and so does
anything that needs the same cell in a plant of its own.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.geometry import CollisionFilterDeclaration, GeometrySet, Role, SceneGraph
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import FixedOffsetFrame, ModelInstanceIndex, PdControllerGains
from pydrake.systems.framework import Diagram

from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.cell import arms
from omtp_drake.cell.described_models import add_described_models
from omtp_drake.cell.parts import parking_pose
from omtp_drake.cell.spawned_objects import object_part_urdf
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import ModelConfig, RobotConfig, Scenario
from omtp_drake.scenario.configs import pose6
from omtp_drake.scenario.conveyor_spawner import pool_kinds

#: Reference poses of the fixed pieces of the cell (world frame).
#: The break beam's housing (its optical link, where the beam leaves, is 2.5 cm in front of
#: it, at (1.575, 1.9, 0.925), as in the course's break_beam.urdf.xacro).
X_W_BREAK_BEAM = RigidTransform(RollPitchYaw(0.0, 0.0, np.pi), [1.6, 1.9, 0.925])
X_W_DELETION_WALL = RigidTransform(RollPitchYaw(0.0, 0.0, 1.5708), [1.2, -5.1, 1.425])
#: Damping gain of the belt's velocity servo (N s/m).
_BELT_KD = 1e4


@dataclass
class ArmHandles:
    """What the station knows of one arm."""

    config: RobotConfig
    arm: ModelInstanceIndex
    gripper: Optional[ModelInstanceIndex]
    pedestal: ModelInstanceIndex
    #: The servo's model of the arm and gripper (base at the origin); also
    #: what differential IK plans with. Held here to keep it alive.
    control_plant: Optional[MultibodyPlant] = None
    #: The servo's command sampler (its initial position is set by
    #: :meth:`Station.initialize_context`).
    sampler: Optional[arms.CommandSampler] = None
    #: The servo (computed torque; with ``ki > 0`` a PID whose integral is its
    #: continuous state).
    controller: Optional[Diagram] = None
    #: What the student hung on the arm or its gripper (model entries with a ``parent``):
    #: in the servo's model too, so it carries their weight as the plant does.
    payloads: list[ModelConfig] = field(default_factory=list)


@dataclass
class CellModels:
    """The model instances :func:`add_cell_models` added to a plant."""

    floor: ModelInstanceIndex
    arms: dict[str, ArmHandles]
    bins: dict[str, ModelInstanceIndex]
    #: bin -> the world frame its base is welded to (its pose is a Context
    #: parameter: a bin can be moved between advances, see Station.move_bin).
    bin_anchors: dict[str, FixedOffsetFrame]
    conveyor: Optional[ModelInstanceIndex]
    cameras: dict[str, ModelInstanceIndex]
    #: Every part (placed and pool) by name.
    parts: dict[str, ModelInstanceIndex]
    #: Names of the pool's parts, in spawn order.
    pool: list[str]
    #: The scenario's models from description files, by name.
    described: dict[str, ModelInstanceIndex] = field(default_factory=dict)


def _add_xacro(parser: Parser, file: str, args: dict | None = None) -> ModelInstanceIndex:
    text = expand_xacro(MODELS_DIR / file, args or {})
    (instance,) = parser.AddModelsFromString(text, "sdf" if ".sdf" in file else "urdf")
    return instance


def _weld(plant: MultibodyPlant, frame_name: str, X_WF: RigidTransform, parent=None) -> None:
    plant.WeldFrames(parent or plant.world_frame(), plant.GetFrameByName(frame_name), X_WF)


def add_cell_models(
    plant: MultibodyPlant, scene_graph: SceneGraph, scenario: Scenario, *, parts: bool = True
) -> CellModels:
    """Adds every model of ``scenario``'s cell to ``plant`` (not finalized), welded at its
    pose: floor, pedestals and arms with grippers, bins, conveyor, break beam, deletion
    wall, camera frames and (with ``parts``) the placed parts and the parked pool.

    Used by :func:`build_station` and by anything that needs the same cell in a plant
    of its own (e.g. a motion planner's collision model).
    """
    parser = Parser(plant)
    floor = _add_xacro(parser, "floor.urdf.xacro")
    _weld(plant, "floor", RigidTransform())
    arm_handles = _add_arms(parser, scenario)
    bins, anchors = _add_bins(parser, scenario)
    conveyor = _add_fixtures(parser, scenario)
    camera_instances = _add_camera_frames(parser, scenario)
    part_instances, pool = _add_parts(parser, scenario) if parts else ({}, [])
    _add_extra_frames(plant, scenario)
    pieces = _own_pieces(scenario)
    described = add_described_models(parser, [m for m in scenario.models if m.name not in pieces])
    hung = _hung(plant, scenario, described)
    _filter_robot_collisions(plant, scene_graph, arm_handles, hung)
    by_name = {m.name: m for m in scenario.models}
    for handles in arm_handles.values():
        on_arm = [handles.arm] + ([handles.gripper] if handles.gripper else [])
        names = {plant.GetModelInstanceName(h) for i in on_arm for h in hung.get(i, [])}
        handles.payloads = [by_name[n] for n in names]
    if conveyor is not None:
        fixed = [floor, *bins.values(), *(h.pedestal for h in arm_handles.values())]
        _filter_belt_collisions(plant, scene_graph, conveyor, fixed)
    return CellModels(
        floor=floor,
        arms=arm_handles,
        bins=bins,
        bin_anchors=anchors,
        conveyor=conveyor,
        cameras=camera_instances,
        parts=part_instances,
        pool=pool,
        described=described,
    )


def _add_extra_frames(plant: MultibodyPlant, scenario: Scenario) -> None:
    """The scenario's extra fixed frames, in order (a frame may hang on an earlier one); a
    name the cell already has is left as the cell has it."""
    for frame in scenario.frames:
        if plant.HasFrameNamed(frame.name):
            continue
        if not plant.HasFrameNamed(frame.parent):
            raise ConfigError(f"frames[{frame.name}].parent {frame.parent!r} is no frame of the cell")
        plant.AddFrame(FixedOffsetFrame(frame.name, plant.GetFrameByName(frame.parent), frame.X_PF()))


def _own_pieces(scenario: Scenario) -> set[str]:
    """The model entries that are course pieces as the student's files write them (bins,
    pedestals): added with their piece, not with the other models."""
    return {b.model for b in scenario.bins if b.model} | {
        r.pedestal_model for r in scenario.robots if r.pedestal_model
    }


def _own_piece(parser: Parser, scenario: Scenario, name: str, what: str) -> ModelInstanceIndex:
    """The scenario's model entry ``name`` (``what`` names the setting), added as its file writes it."""
    models = {m.name: m for m in scenario.models}
    if name not in models:
        raise ConfigError(f"{what} {name!r} is no model of the scenario: {sorted(models)}")
    return add_described_models(parser, [models[name]])[name]


def _add_arms(parser: Parser, scenario: Scenario) -> dict[str, ArmHandles]:
    """Each robot's pedestal and arm with its gripper, welded at the robot's pose."""
    plant = parser.plant()
    arm_handles: dict[str, ArmHandles] = {}
    for robot in scenario.robots:
        x, y = robot.xy
        if robot.pedestal_model:  # the student's own, welded where their file puts it
            pedestal = _own_piece(
                parser, scenario, robot.pedestal_model, f"robots[{robot.name}].pedestal_model"
            )
        else:
            pedestal = _add_xacro(
                parser,
                "pedestal.urdf.xacro",
                {"name": f"{robot.name}_pedestal", "height": robot.pedestal_height},
            )
            _weld(plant, f"{robot.name}_pedestal_link", RigidTransform([x, y, 0.0]))
        arm, gripper = arms.add_arm_models(parser, robot)
        _weld(plant, f"{robot.name}_base_link", arms.base_pose(robot))
        arm_handles[robot.name] = ArmHandles(robot, arm, gripper, pedestal)
    return arm_handles


def _add_bins(
    parser: Parser, scenario: Scenario
) -> tuple[dict[str, ModelInstanceIndex], dict[str, FixedOffsetFrame]]:
    """The bins, each welded to a world frame of its own (its anchor): the catalogue's, or
    the student's own (``bin.model``: a model entry, loaded as its file writes it)."""
    plant = parser.plant()
    bins, anchors = {}, {}
    for b in scenario.bins:
        if b.model:
            bins[b.name] = _own_piece(parser, scenario, b.model, f"bins[{b.name}].model")
        else:
            bins[b.name] = _add_xacro(parser, "bin.urdf.xacro", {"name": b.name})
        anchors[b.name] = plant.AddFrame(FixedOffsetFrame(f"{b.name}_anchor", plant.world_frame(), b.X_WB()))
        plant.WeldFrames(anchors[b.name], plant.GetFrameByName(f"{b.name}_base_link", bins[b.name]))
    return bins, anchors


def _add_fixtures(parser: Parser, scenario: Scenario) -> Optional[ModelInstanceIndex]:
    """The conveyor (with its belt's velocity servo gains), break beam and deletion
    wall of the scenario; returns the conveyor's instance (None: no conveyor)."""
    plant = parser.plant()
    conveyor = None
    if scenario.conveyor is not None:
        conveyor = _add_xacro(parser, "conveyor.urdf.xacro", scenario.conveyor.model_args())
        _weld(plant, "conveyor_base", scenario.conveyor.X_WF())
        for index in plant.GetJointActuatorIndices():
            actuator = plant.get_joint_actuator(index)
            if actuator.model_instance() == conveyor:
                actuator.set_controller_gains(PdControllerGains(p=0.0, d=_BELT_KD))
    if scenario.break_beam:
        _add_xacro(parser, "break_beam.urdf.xacro")
        moved = scenario.break_beam_pose
        _weld(plant, "break_beam_base_link", pose6(moved) if moved else X_W_BREAK_BEAM)
    if scenario.deletion_wall and not scenario.deletion_wall_model:  # (else: a model entry)
        _add_xacro(parser, "deletion_wall.urdf.xacro")
        moved = scenario.deletion_wall_pose
        _weld(plant, "deletion_wall", pose6(moved) if moved else X_W_DELETION_WALL)
    return conveyor


def _add_camera_frames(parser: Parser, scenario: Scenario) -> dict[str, ModelInstanceIndex]:
    """Each camera's model, its frame welded to its parent at the camera's pose."""
    plant = parser.plant()
    camera_instances = {}
    for cam in scenario.cameras:
        args = {"name": cam.name, "housing": "true" if cam.housing else "false"}
        camera_instances[cam.name] = _add_xacro(parser, "logical_camera.urdf.xacro", args)
        parent = plant.GetFrameByName(cam.parent) if cam.parent != "world" else plant.world_frame()
        _weld(plant, f"{cam.name}_frame", cam.X_PC(), parent=parent)
    return camera_instances


def _add_parts(parser: Parser, scenario: Scenario) -> tuple[dict[str, ModelInstanceIndex], list[str]]:
    """The placed parts at their poses, then the pool's ``object_k`` at their parking poses."""
    plant = parser.plant()
    instances: dict[str, ModelInstanceIndex] = {}

    def add(name: str, size: float, mass: float, X_WP: RigidTransform) -> None:
        instances[name] = _add_xacro(parser, "part.urdf.xacro", {"name": name, "size": size, "mass": mass})
        plant.SetDefaultFloatingBaseBodyPose(plant.GetBodyByName(name, instances[name]), X_WP)

    for part in scenario.parts:
        add(part.name, part.size, part.mass, RigidTransform(RollPitchYaw(part.rpy), part.xyz))
    pool = scenario.pool_names()
    objects = {o.name: o for o in scenario.spawner.objects} if scenario.spawner is not None else {}
    kinds = pool_kinds(scenario.spawner, scenario.seed, pool)
    for name in pool:
        obj = objects.get(kinds.get(name, ""))
        if obj is not None and obj.mesh_file:
            # The spawner plugin's model of the object this pool part is spawned as.
            (instances[name],) = parser.AddModelsFromString(object_part_urdf(name, obj), "urdf")
            body = plant.GetBodyByName(name, instances[name])
            plant.SetDefaultFloatingBaseBodyPose(body, parking_pose(len(instances) - 1))
        else:
            add(name, scenario.pool_part_size, scenario.pool_part_mass, parking_pose(len(instances)))
    return instances, pool


def _geometries(plant: MultibodyPlant, scene_graph: SceneGraph, bodies: list) -> list:
    inspector = scene_graph.model_inspector()
    ids = []
    for body in bodies:
        ids += inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(body.index()), Role.kProximity)
    return ids


def _filter_belt_collisions(
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    conveyor: ModelInstanceIndex,
    fixed: list[ModelInstanceIndex],
) -> None:
    """The belt's moving surface is the drive, not an obstacle: it touches what rides it,
    never the cell's fixed pieces (the floor, bins, pedestals, the break beam and the
    deletion wall, which stands just past its end: a tilted belt's surface, travelling and
    reaching upstream beyond the drawn belt, would run into them)."""
    belt = [plant.GetBodyByName("conveyor_belt", conveyor)]
    for name in ("break_beam", "deletion_wall"):
        if plant.HasModelInstanceNamed(name):
            fixed = [*fixed, plant.GetModelInstanceByName(name)]
    others = [plant.get_body(b) for instance in fixed for b in plant.GetBodyIndices(instance)]
    scene_graph.collision_filter_manager().Apply(
        CollisionFilterDeclaration().ExcludeBetween(
            GeometrySet(_geometries(plant, scene_graph, belt)),
            GeometrySet(_geometries(plant, scene_graph, others)),
        )
    )


def _hung(
    plant: MultibodyPlant, scenario: Scenario, described: dict[str, ModelInstanceIndex]
) -> dict[ModelInstanceIndex, list[ModelInstanceIndex]]:
    """The described models hung on a link of another model (``parent``), by that model."""
    hung: dict[ModelInstanceIndex, list[ModelInstanceIndex]] = {}
    for model in scenario.models:
        if model.parent and model.name in described:
            owner = plant.GetFrameByName(model.parent).body().model_instance()
            hung.setdefault(owner, []).append(described[model.name])
    return hung


def _filter_robot_collisions(
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    arm_handles: dict[str, ArmHandles],
    hung: dict[ModelInstanceIndex, list[ModelInstanceIndex]],
) -> None:
    """No contact between the links of one arm, its gripper, its pedestal and what the
    student hung on them (``hung``: a camera on the wrist is clamped there, as one robot)."""
    inspector = scene_graph.model_inspector()
    for handles in arm_handles.values():
        geometries = []
        instances = [handles.arm, handles.pedestal] + ([handles.gripper] if handles.gripper else [])
        instances += [h for i in list(instances) for h in hung.get(i, [])]
        for instance in instances:
            for body_index in plant.GetBodyIndices(instance):
                frame_id = plant.GetBodyFrameIdOrThrow(body_index)
                geometries += inspector.GetGeometries(frame_id, Role.kProximity)
        scene_graph.collision_filter_manager().Apply(
            CollisionFilterDeclaration().ExcludeWithin(GeometrySet(geometries))
        )
