"""The factory station: one function builds the whole cell as a Drake diagram.

:func:`build_station` turns a :class:`~omtp_drake.scenario.Scenario` into a
diagram holding the MultibodyPlant (floor, conveyor, bins, pedestals, UR arms
with vacuum grippers, logical cameras, break beam, deletion wall, parts), the
SceneGraph, the arms' position servos, the logical cameras and, optionally, a
Meshcat visualizer.

Exported ports are named ``<instance>.<signal>``:

=============================  ======  ==========================================
port                           kind    meaning
=============================  ======  ==========================================
``robotN.position``            input   desired joint positions (6)
``robotN.position_measured``   output  joint positions (6)
``robotN.velocity_estimated``  output  joint velocities (6)
``robotN.state_estimated``     output  [q; v] (12)
``robotN.torque_commanded``    output  joint torques of the servo (6)
``suctionN.command``           input   vacuum on (> 0.5) / off (scenarios with parts)
``suctionN.state``             output  :class:`GripperState`
``conveyor.power``             output  belt power, percent
``break_beam.state``           output  [object_detected, range]
``<camera>.image``             output  :class:`LogicalCameraImage`
``body_poses``                 output  world poses of every body
``contact_results``            output  the plant's contact results
``query_object``               output  SceneGraph's query object
``plant_state``                output  the plant's full state
=============================  ======  ==========================================
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.geometry import (
    CollisionFilterDeclaration,
    GeometrySet,
    Meshcat,
    MeshcatVisualizer,
    MeshcatVisualizerParams,
    Role,
    SceneGraph,
)
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant
from pydrake.multibody.math import SpatialVelocity
from pydrake.multibody.tree import ModelInstanceIndex, PdControllerGains
from pydrake.systems.framework import Context, Diagram, DiagramBuilder
from pydrake.systems.primitives import Demultiplexer

from omtp_drake import arms
from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.conveyor import BreakBeam, ConveyorBelt
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.logical_camera import LogicalCamera, add_logical_camera
from omtp_drake.parts import PartManager, parking_pose
from omtp_drake.scenario import RobotConfig, Scenario, load_scenario
from omtp_drake.suction import (SuctionConstraints, SuctionGripper, add_suction_gripper,
                                connect_spatial_forces, declare_suction_constraints)

_log = logging.getLogger(__name__)

#: Reference poses of the fixed pieces of the cell (world frame).
X_W_CONVEYOR = RigidTransform([1.2, 0.0, 0.0])
X_W_BREAK_BEAM = RigidTransform(RollPitchYaw(0.0, 0.0, np.pi), [1.575, 1.9, 0.925])
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


@dataclass
class Station:
    """A built factory diagram and handles into it."""

    scenario: Scenario
    diagram: Diagram
    plant: MultibodyPlant
    scene_graph: SceneGraph
    arms: dict[str, ArmHandles]
    cameras: dict[str, LogicalCamera]
    #: Every part (placed and pool) by name.
    parts: dict[str, ModelInstanceIndex]
    #: Names of the pool's parts, in spawn order.
    pool: list[str]
    meshcat: Optional[Meshcat] = None
    visualizer: Optional[MeshcatVisualizer] = None
    conveyor: Optional[ConveyorBelt] = None
    break_beam: Optional[BreakBeam] = None
    part_manager: Optional[PartManager] = None
    #: robot -> its vacuum gripper system (absent without parts to grip).
    grippers: dict[str, SuctionGripper] = field(default_factory=dict)
    #: robot -> the weld backend's constraints (weld backend only).
    suction_constraints: dict[str, SuctionConstraints] = field(default_factory=dict)
    _interpolators: dict = field(default_factory=dict, repr=False)

    def arm(self, name: str) -> ArmHandles:
        """Handles of the arm ``name`` (``robot1``...)."""
        if name not in self.arms:
            raise UnknownNameError("robot", name, self.arms)
        return self.arms[name]

    def create_context(self, positions: dict[str, np.ndarray] | None = None,
                       *, hold: bool = True) -> Context:
        """A context of the station with each arm at rest at its initial pose.

        ``positions`` overrides the pose of some arms (name -> joint positions).
        With ``hold``, each arm's position command is fixed to its pose, so a
        simulation of the station alone holds still.
        """
        context = self.diagram.CreateDefaultContext()
        for name, handles in self.arms.items():
            q = (positions or {}).get(name)
            if q is None:
                q = arms.named_pose(handles.config.initial_pose, handles.config)
            self.set_arm_positions(context, name, q)
            if hold:
                self.diagram.GetInputPort(f"{name}.position").FixValue(context, q)
                if name in self.grippers:
                    self.diagram.GetInputPort(
                        f"{suction_name(self.arms[name].config)}.command").FixValue(context, [0.0])
        self.initialize_context(context)
        return context

    def initialize_context(self, root_context: Context) -> None:
        """What every new context needs: pool parked, suction constraints off."""
        self.park_pool(root_context)
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        for constraints in self.suction_constraints.values():
            constraints.deactivate_all(self.plant, plant_context)

    def suction_name(self, robot: str) -> str:
        """The name (port prefix) of ``robot``'s vacuum gripper: ``suction1``..."""
        if robot not in self.grippers:
            raise UnknownNameError("robot with a vacuum gripper (and parts to grip)", robot,
                                   self.grippers)
        return suction_name(self.arms[robot].config)

    def set_arm_positions(self, root_context: Context, name: str, q: np.ndarray) -> None:
        """Puts arm ``name`` at rest at ``q`` and starts its servo from there.

        ``root_context`` is the context of the station's diagram or of a diagram
        containing it.
        """
        handles = self.arm(name)
        q = np.asarray(q, dtype=float)
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        self.plant.SetPositions(plant_context, handles.arm, q)
        self.plant.SetVelocities(plant_context, handles.arm, np.zeros_like(q))
        interpolator = self._interpolators[name]
        interpolator.set_initial_position(
            interpolator.GetMyMutableContextFromRoot(root_context), q)

    def park_pool(self, root_context: Context) -> None:
        """Puts every parked part of the pool exactly at its parking pose, held there."""
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        book = self.part_manager.book(self.part_manager.GetMyContextFromRoot(root_context))
        for slot, record in enumerate(book.parts):
            if record.state == "parked":
                self.park(plant_context, record.name)

    def park(self, plant_context: Context, name: str) -> None:
        """Parks pool part ``name``: at rest at its parking pose, its joint locked.

        A locked joint leaves the contact solver's problem: parked parts cost nothing.
        """
        body = self.plant.GetBodyByName(name, self.parts[name])
        self.plant.SetFreeBodyPose(plant_context, body, parking_pose(self.pool.index(name)))
        self.plant.SetFreeBodySpatialVelocity(plant_context, body, SpatialVelocity.Zero())
        self._free_joint(name).Lock(plant_context)

    def unpark(self, plant_context: Context, name: str) -> None:
        """Frees pool part ``name`` (the caller then puts it where it belongs)."""
        self._free_joint(name).Unlock(plant_context)

    def _free_joint(self, name: str):
        (index,) = self.plant.GetJointIndices(self.parts[name])
        return self.plant.get_joint(index)


def suction_name(robot: RobotConfig) -> str:
    """``vacuum_gripper1`` -> ``suction1`` (the gripper system and its ports)."""
    if robot.gripper.startswith("vacuum_gripper"):
        return "suction" + robot.gripper[len("vacuum_gripper"):]
    return f"{robot.gripper}_suction"


def _add_xacro(parser: Parser, file: str, args: dict | None = None) -> ModelInstanceIndex:
    text = expand_xacro(MODELS_DIR / file, args or {})
    (instance,) = parser.AddModelsFromString(text, "sdf" if ".sdf" in file else "urdf")
    return instance


def _weld(plant: MultibodyPlant, frame_name: str, X_WF: RigidTransform, parent=None) -> None:
    plant.WeldFrames(parent or plant.world_frame(), plant.GetFrameByName(frame_name), X_WF)


@dataclass
class CellModels:
    """The model instances :func:`add_cell_models` added to a plant."""

    floor: ModelInstanceIndex
    arms: dict[str, ArmHandles]
    bins: dict[str, ModelInstanceIndex]
    conveyor: Optional[ModelInstanceIndex]
    cameras: dict[str, ModelInstanceIndex]
    #: Every part (placed and pool) by name.
    parts: dict[str, ModelInstanceIndex]
    #: Names of the pool's parts, in spawn order.
    pool: list[str]


def add_cell_models(plant: MultibodyPlant, scene_graph: SceneGraph, scenario: Scenario,
                    *, parts: bool = True) -> CellModels:
    """Adds every model of ``scenario``'s cell to ``plant`` (not finalized), welded at its
    pose: floor, pedestals and arms with grippers, bins, conveyor, break beam, deletion
    wall, camera frames and (with ``parts``) the placed parts and the parked pool.

    Used by :func:`build_station` and by anything that needs the same cell in a plant
    of its own (e.g. a motion planner's collision model).
    """
    parser = Parser(plant)
    floor = _add_xacro(parser, "floor.urdf.xacro")
    _weld(plant, "floor", RigidTransform())
    arm_handles: dict[str, ArmHandles] = {}
    for robot in scenario.robots:
        x, y = robot.xy
        pedestal = _add_xacro(
            parser, "pedestal.urdf.xacro",
            {"name": f"{robot.name}_pedestal", "height": robot.pedestal_height})
        _weld(plant, f"{robot.name}_pedestal_link",
              RigidTransform(RollPitchYaw(0, 0, robot.yaw), [x, y, 0.0]))
        arm, gripper = arms.add_arm_models(parser, robot)
        _weld(plant, f"{robot.name}_base_link", arms.base_pose(robot))
        arm_handles[robot.name] = ArmHandles(robot, arm, gripper, pedestal)

    bins = {}
    for b in scenario.bins:
        bins[b.name] = _add_xacro(parser, "bin.urdf.xacro", {"name": b.name})
        _weld(plant, f"{b.name}_base_link", b.X_WB())

    conveyor = None
    if scenario.conveyor is not None:
        conveyor = _add_xacro(parser, "conveyor.urdf.xacro")
        _weld(plant, "conveyor_base", X_W_CONVEYOR)
    if scenario.break_beam:
        _add_xacro(parser, "break_beam.urdf.xacro")
        _weld(plant, "break_beam_base_link", X_W_BREAK_BEAM)
    if scenario.deletion_wall:
        _add_xacro(parser, "deletion_wall.urdf.xacro")
        _weld(plant, "deletion_wall", X_W_DELETION_WALL)

    camera_instances = {}
    for cam in scenario.cameras:
        camera_instances[cam.name] = _add_xacro(parser, "logical_camera.urdf.xacro", {"name": cam.name})
        parent = plant.GetFrameByName(cam.parent) if cam.parent != "world" else plant.world_frame()
        _weld(plant, f"{cam.name}_frame", cam.X_PC(), parent=parent)

    part_instances: dict[str, ModelInstanceIndex] = {}
    pool: list[str] = []
    if parts:
        for part in scenario.parts:
            part_instances[part.name] = _add_xacro(
                parser, "part.urdf.xacro", {"name": part.name, "size": part.size, "mass": part.mass})
            plant.SetDefaultFloatingBaseBodyPose(
                plant.GetBodyByName(part.name, part_instances[part.name]),
                RigidTransform(RollPitchYaw(part.rpy), part.xyz))
        taken = set(part_instances)
        k = 1
        while len(pool) < scenario.part_pool:
            name = f"object_{k}"
            k += 1
            if name in taken:
                continue
            pool.append(name)
            part_instances[name] = _add_xacro(parser, "part.urdf.xacro", {
                "name": name, "size": scenario.pool_part_size, "mass": scenario.pool_part_mass})
            plant.SetDefaultFloatingBaseBodyPose(
                plant.GetBodyByName(name, part_instances[name]), parking_pose(len(pool) - 1))

    _filter_robot_collisions(plant, scene_graph, arm_handles)
    if conveyor is not None:
        for index in plant.GetJointActuatorIndices():
            actuator = plant.get_joint_actuator(index)
            if actuator.model_instance() == conveyor:
                actuator.set_controller_gains(PdControllerGains(p=0.0, d=_BELT_KD))
    return CellModels(floor=floor, arms=arm_handles, bins=bins, conveyor=conveyor,
                      cameras=camera_instances, parts=part_instances, pool=pool)


def build_station(
    scenario: Scenario | str,
    *,
    meshcat: Optional[Meshcat] = None,
) -> Station:
    """Builds the factory diagram described by ``scenario`` (a Scenario, name or path).

    With ``meshcat``, a MeshcatVisualizer is added. To drive the station from
    other systems, add ``station.diagram`` to a builder of your own.
    """
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    scenario.validate()
    inner = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(scenario.plant_config, inner)
    plant.mutable_gravity_field().set_gravity_vector(scenario.gravity)
    models = add_cell_models(plant, scene_graph, scenario)
    floor, arm_handles, conveyor = models.floor, models.arms, models.conveyor
    camera_instances, parts, pool = models.cameras, models.parts, models.pool

    # Weld-backend grippers: their run-time constraints must exist before Finalize.
    constraints: dict[str, SuctionConstraints] = {}
    if parts and scenario.suction.backend == "weld":
        placeholder = plant.GetBodyByName(next(iter(parts)), parts[next(iter(parts))])
        for name, handles in arm_handles.items():
            if handles.gripper is not None:
                cup = plant.GetBodyByName(f"{handles.config.gripper}_cup", handles.gripper)
                constraints[name] = declare_suction_constraints(plant, cup, placeholder)
    plant.Finalize()
    for handles in arm_handles.values():
        plant.SetDefaultPositions(
            handles.arm, arms.named_pose(handles.config.initial_pose, handles.config))

    # Arm servos.
    interpolators = {}
    for name, handles in arm_handles.items():
        interpolator, controller, handles.control_plant = arms.add_arm_controller(
            inner, plant, handles.arm, handles.config)
        interpolators[name] = interpolator
        inner.ExportInput(interpolator.get_input_port(), f"{name}.position")
        state = plant.get_state_output_port(handles.arm)
        n = plant.num_positions(handles.arm)
        demux = inner.AddNamedSystem(f"{name}.demux", Demultiplexer([n, n]))
        inner.Connect(state, demux.get_input_port())
        inner.ExportOutput(demux.get_output_port(0), f"{name}.position_measured")
        inner.ExportOutput(demux.get_output_port(1), f"{name}.velocity_estimated")
        inner.ExportOutput(state, f"{name}.state_estimated")
        inner.ExportOutput(controller.get_output_port_control(), f"{name}.torque_commanded")

    belt = None
    if conveyor is not None:
        belt = inner.AddNamedSystem("conveyor", ConveyorBelt(
            scenario.conveyor.power, stop_on_beam=scenario.conveyor.stop_on_beam))
        inner.Connect(belt.GetOutputPort("desired_state"), plant.get_desired_state_input_port(conveyor))
        inner.ExportOutput(belt.GetOutputPort("power"), "conveyor.power")
    beam = None
    if scenario.break_beam:
        part_bodies = [plant.GetBodyByName(n, i) for n, i in parts.items()]
        boxes = [(np.zeros(3), np.full(3, scenario.part_size(n) / 2)) for n in parts]
        beam = inner.AddNamedSystem("break_beam", BreakBeam(
            plant, plant.GetFrameByName("break_beam_optical_link"), part_bodies, boxes))
        inner.Connect(plant.get_body_poses_output_port(), beam.GetInputPort("body_poses"))
        inner.ExportOutput(beam.GetOutputPort("state"), "break_beam.state")
        if belt is not None:
            inner.Connect(beam.GetOutputPort("state"), belt.GetInputPort("beam"))
    if belt is not None and beam is None and scenario.conveyor.stop_on_beam:
        raise ConfigError("conveyor.stop_on_beam needs break_beam: true")
    part_manager = inner.AddNamedSystem("parts", PartManager(pool, scenario.spawner))

    # Vacuum grippers (only when there are parts to grip).
    grippers: dict[str, SuctionGripper] = {}
    if parts:
        part_bodies = [plant.GetBodyByName(n, i) for n, i in parts.items()]
        for name, handles in arm_handles.items():
            if handles.gripper is None:
                continue
            cup = plant.GetBodyByName(f"{handles.config.gripper}_cup", handles.gripper)
            suction = suction_name(handles.config)
            grippers[name] = add_suction_gripper(
                inner, plant, cup, part_bodies, scenario.suction, suction)
            inner.ExportInput(grippers[name].GetInputPort("command"), f"{suction}.command")
            inner.ExportOutput(grippers[name].GetOutputPort("state"), f"{suction}.state")
        connect_spatial_forces(inner, plant, list(grippers.values()))

    cameras: dict[str, LogicalCamera] = {}
    for cam in scenario.cameras:
        cameras[cam.name] = add_logical_camera(
            inner, plant, scene_graph, plant.GetFrameByName(f"{cam.name}_frame"), cam,
            exclude=[camera_instances[cam.name], floor], seed=scenario.seed)
        inner.ExportOutput(cameras[cam.name].GetOutputPort("image"), f"{cam.name}.image")

    inner.ExportOutput(plant.get_body_poses_output_port(), "body_poses")
    inner.ExportOutput(plant.get_contact_results_output_port(), "contact_results")
    inner.ExportOutput(plant.get_state_output_port(), "plant_state")
    inner.ExportOutput(scene_graph.get_query_output_port(), "query_object")

    visualizer = None
    if meshcat is not None:
        visualizer = MeshcatVisualizer.AddToBuilder(
            inner, scene_graph, meshcat, MeshcatVisualizerParams(role=Role.kIllustration))

    diagram = inner.Build()
    diagram.set_name("station")
    return Station(
        scenario=scenario, diagram=diagram, plant=plant, scene_graph=scene_graph,
        arms=arm_handles, cameras=cameras, parts=parts, pool=pool, meshcat=meshcat,
        visualizer=visualizer, conveyor=belt, break_beam=beam, part_manager=part_manager,
        grippers=grippers, suction_constraints=constraints, _interpolators=interpolators)


def _filter_robot_collisions(
    plant: MultibodyPlant, scene_graph: SceneGraph, arm_handles: dict[str, ArmHandles]
) -> None:
    """No contact between the links of one arm, its gripper and its pedestal."""
    inspector = scene_graph.model_inspector()
    for handles in arm_handles.values():
        geometries = []
        instances = [handles.arm, handles.pedestal] + ([handles.gripper] if handles.gripper else [])
        for instance in instances:
            for body_index in plant.GetBodyIndices(instance):
                frame_id = plant.GetBodyFrameIdOrThrow(body_index)
                geometries += inspector.GetGeometries(frame_id, Role.kProximity)
        scene_graph.collision_filter_manager().Apply(
            CollisionFilterDeclaration().ExcludeWithin(GeometrySet(geometries)))
