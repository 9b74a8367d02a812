"""The factory station: one function builds the whole cell as a Drake diagram.

:func:`build_station` turns a :class:`~omtp_drake.scenario.Scenario` into a
diagram holding the MultibodyPlant (floor, conveyor, bins, pedestals, UR arms
with vacuum grippers, logical cameras, break beam, deletion wall, parts), the
SceneGraph, the arms' position servos, the vacuum grippers, the belt, the break
beam, the logical cameras and, optionally, a Meshcat visualizer. Each concern
is added by a helper of its own.

Some changes to the world are not a system's to make (a system may not write
another system's Context): spawning and disposing of parts, making a weld
gripper's constraints, shifting the belt surface back. A plain ``Simulator``
on this diagram therefore never spawns a part and never attaches one with the
weld backend: run it with :class:`omtp_drake.sim.driver.Driver` (what
:class:`omtp_drake.sim.runtime.FactoryRuntime` does), and initialise every new
Context with :meth:`Station.initialize_context`.

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
``<camera>.color_image``       output  RGBA image (cameras with ``rgbd: true``)
``<camera>.depth_image``       output  depth image, m (cameras with ``rgbd: true``)
``<camera>.label_image``       output  label image, body index (``rgbd: true``)
``<sensor>.color_image``       output  a model's camera sensor: RGBA, noisy (``depth_camera``)
``<sensor>.depth_image``       output  a model's camera sensor: depth, m
``<sensor>.point_cloud``       output  a model's depth sensor: points in its optical frame
``body_poses``                 output  world poses of every body
``contact_results``            output  the plant's contact results
``query_object``               output  SceneGraph's query object
``plant_state``                output  the plant's full state
=============================  ======  ==========================================
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Collection
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.geometry import (
    Meshcat,
    MeshcatVisualizer,
    MeshcatVisualizerParams,
    Role,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant
from pydrake.multibody.tree import FixedOffsetFrame, ModelInstanceIndex
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, InputPort

from omtp_drake.cell import arms
from omtp_drake.cell.arm_servos import add_arm_servos
from omtp_drake.cell.cell_models import ArmHandles, CellModels, add_cell_models
from omtp_drake.cell.conveyor import BeltGeometry, BreakBeam, ConveyorBelt
from omtp_drake.cell.depth_camera import DepthCamera, add_model_cameras
from omtp_drake.cell.joint_controllers import JointControllers, add_joint_controllers, declare_joint_drives
from omtp_drake.cell.logical_camera import LogicalCamera, add_logical_camera
from omtp_drake.cell.parts import PartStates
from omtp_drake.cell.rest_clock import RestClock
from omtp_drake.cell.suction import EVERY_STEP, CommandPolling, SuctionGripper
from omtp_drake.cell.suction_constraints import SuctionConstraints, declare_suction_constraints
from omtp_drake.cell.suction_holds import WeldSuctionGripper, add_suction_gripper, connect_spatial_forces
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario import RobotConfig, Scenario, require_scenario
from omtp_drake.scenario.conveyor_spawner import pool_kinds

_log = logging.getLogger(__name__)

#: The station's public names (the cell's models live in :mod:`omtp_drake.cell.cell_models`
#: and are named here too, for their users).
__all__ = ["ArmHandles", "CellModels", "Station", "add_cell_models", "build_station", "suction_name"]


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
    #: robot -> its vacuum gripper system (absent without parts to grip).
    grippers: dict[str, SuctionGripper] = field(default_factory=dict)
    bin_anchors: dict[str, FixedOffsetFrame] = field(default_factory=dict)
    #: Since when each part has been still (None when the scenario's parts never sleep).
    rest_clock: Optional[RestClock] = None
    #: The scenario's models from description files, and their camera and depth sensors.
    models: dict[str, ModelInstanceIndex] = field(default_factory=dict)
    depth_cameras: dict[str, DepthCamera] = field(default_factory=dict)
    #: The models' ros_control joint controllers (None: no model has a ros_control plugin).
    joint_controllers: Optional[JointControllers] = None

    def arm(self, name: str) -> ArmHandles:
        """Handles of the arm ``name`` (``robot1``...)."""
        if name not in self.arms:
            raise UnknownNameError("robot", name, self.arms)
        return self.arms[name]

    @functools.cached_property
    def part_states(self) -> PartStates:
        """Which parts are parked, asleep or awake in a Context, and the edits between
        those states (:class:`omtp_drake.cell.parts.PartStates`)."""
        return PartStates(self.plant, self.scene_graph, self.parts)

    @functools.cached_property
    def pool_kinds(self) -> dict[str, str]:
        """pool part -> the spawner's object it is built as ({} without the course's
        plugin's ``objects``; :func:`omtp_drake.scenario.conveyor_spawner.pool_kinds`)."""
        return pool_kinds(self.scenario.spawner, self.scenario.seed, self.pool)

    @functools.cached_property
    def belt(self) -> Optional[BeltGeometry]:
        """Where the belt is (None without a conveyor)."""
        conveyor = self.scenario.conveyor
        return BeltGeometry.of(conveyor) if conveyor is not None else None

    # ------------------------------------------------------------------ contexts

    def initialize_context(
        self,
        root_context: Context,
        positions: Optional[dict[str, np.ndarray]] = None,
        *,
        hold: Optional[list[InputPort]] = None,
    ) -> None:
        """What every new Context of a diagram holding the station needs.

        Each arm at rest at its initial pose (``positions``: robot -> joint
        positions instead) with its servo started there; the pool's parts
        parked; the weld grippers' constraints off. ``hold``: station input
        ports nobody drives, fixed so the station holds still (an arm's
        ``position`` at its pose, a gripper's ``command`` off). An arm whose
        ``position`` is held is also locked (:meth:`set_arm_locked`): it never
        moves, and the contact solver drops its degrees of freedom (less CPU per
        simulated second: bench/README.md, "Measured").
        ``root_context`` is the Context of the station's diagram or of a
        diagram containing it.
        """
        positions = dict(positions or {})
        for robot in positions:
            self.arm(robot)
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        for name, handles in self.arms.items():
            q = positions.get(name)
            if q is None:
                q = arms.named_pose(handles.config.initial_pose, handles.config)
            self.set_arm_positions(root_context, name, q)
        for name in self.pool:
            self.part_states.park(root_context, name)
        for gripper in self.grippers.values():
            if isinstance(gripper, WeldSuctionGripper):
                gripper.constraints.deactivate_all(self.plant, plant_context)
        station_context = self.diagram.GetMyMutableContextFromRoot(root_context)
        for port in hold or []:
            robot, _, signal = port.get_name().partition(".")
            if signal == "position":
                port.FixValue(station_context, self.plant.GetPositions(plant_context, self.arm(robot).arm))
                self.set_arm_locked(root_context, robot, True)
            elif signal == "command":
                port.FixValue(station_context, [0.0])
            else:
                raise ConfigError(f"cannot hold station input {port.get_name()!r}")

    def create_context(self, positions: Optional[dict[str, np.ndarray]] = None) -> Context:
        """A Context of the station alone, initialised, every input held (for
        static queries and simulations of the station holding still)."""
        context = self.diagram.CreateDefaultContext()
        ports = [self.diagram.get_input_port(i) for i in range(self.diagram.num_input_ports())]
        self.initialize_context(context, positions, hold=ports)
        return context

    def set_arm_positions(self, root_context: Context, name: str, q) -> None:
        """Puts arm ``name`` at rest at ``q`` and starts its servo from there."""
        handles = self.arm(name)
        q = arms.check_joint_positions(q, handles.config)
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        self.plant.SetPositions(plant_context, handles.arm, q)
        self.plant.SetVelocities(plant_context, handles.arm, np.zeros_like(q))
        sampler = handles.sampler
        if sampler is None:
            raise ConfigError(f"arm {name!r} has no servo (the station is not built)")
        sampler.set_initial_position(root_context, q)

    def set_arm_locked(self, root_context: Context, name: str, locked: bool) -> None:
        """Locks (or unlocks) arm ``name``'s joints where they are: a locked arm
        does not move whatever its servo commands."""
        arms.lock_arm(
            self.plant, self.plant.GetMyMutableContextFromRoot(root_context), self.arm(name).arm, locked
        )

    def clear_servo_integral(self, root_context: Context, name: str) -> None:
        """Zeroes arm ``name``'s servo integral, if it has one (after a blocked arm is
        freed, so the error integrated while it was held does not throw it off)."""
        controller = self.arm(name).controller
        if controller is None:
            raise ConfigError(f"arm {name!r} has no servo (the station is not built)")
        servo_context = controller.GetMyMutableContextFromRoot(root_context)
        if servo_context.num_continuous_states():
            servo_context.get_mutable_continuous_state_vector().SetZero()

    # ------------------------------------------------------------------ grippers

    def suction_name(self, robot: str) -> str:
        """The name (port prefix) of ``robot``'s vacuum gripper: ``suction1``..."""
        if robot not in self.grippers:
            raise UnknownNameError("robot with a vacuum gripper (and parts to grip)", robot, self.grippers)
        return suction_name(self.arms[robot].config)

    # ------------------------------------------------------------------ bins

    def bin_pose(self, root_context: Context, name: str) -> RigidTransform:
        """``X_WB``: where bin ``name``'s base is now."""
        if name not in self.bin_anchors:
            raise UnknownNameError("bin", name, self.bin_anchors)
        return self.bin_anchors[name].CalcPoseInWorld(self.plant.GetMyContextFromRoot(root_context))

    def move_bin(self, root_context: Context, name: str, X_WB: RigidTransform) -> None:
        """Puts bin ``name``'s base at ``X_WB`` (between advances: a world edit)."""
        if name not in self.bin_anchors:
            raise UnknownNameError("bin", name, self.bin_anchors)
        self.bin_anchors[name].SetPoseInParentFrame(
            self.plant.GetMyMutableContextFromRoot(root_context), X_WB
        )


def suction_name(robot: RobotConfig) -> str:
    """``vacuum_gripper1`` -> ``suction1`` (the gripper system and its ports)."""
    if robot.gripper.startswith("vacuum_gripper"):
        return "suction" + robot.gripper[len("vacuum_gripper") :]
    return f"{robot.gripper}_suction"


# ----------------------------------------------------------------------------- the station


def build_station(
    scenario: Scenario,
    *,
    meshcat: Optional[Meshcat] = None,
    controlled: Collection[str] = (),
) -> Station:
    """Builds the factory diagram described by ``scenario`` (validated here, once
    per build; a name or path becomes a Scenario in
    :func:`omtp_drake.scenario.load_scenario`).

    With ``meshcat``, a MeshcatVisualizer is added. To drive the station from
    other systems, add ``station.diagram`` to a builder of your own; ``controlled``
    names the robots whose gripper command one of them writes (:func:`_gripper_polling`).
    """
    require_scenario(scenario, "build_station").validate()
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(scenario.plant_config, builder)
    plant.mutable_gravity_field().set_gravity_vector(scenario.gravity)
    models = add_cell_models(plant, scene_graph, scenario)
    constraints = _declare_weld_constraints(plant, scenario, models)
    drives = declare_joint_drives(plant, scenario.models, models.described)
    plant.Finalize()
    joint_controllers = add_joint_controllers(builder, plant, drives, models.described)
    add_arm_servos(builder, plant, models.arms, scenario.gravity)
    belt = _add_conveyor(builder, plant, scenario, models)
    beam = _add_break_beam(builder, plant, scenario, models, belt)
    grippers = _add_grippers(builder, plant, scenario, models, constraints, controlled)
    cameras, depth_cameras = _add_cameras(builder, plant, scene_graph, scenario, models, meshcat)
    rest_clock = None
    if scenario.sleep.enabled and models.parts:
        # Sampled by the driver's PartSleep, only while a part is free (its class doc).
        rest_clock = RestClock.AddToDiagram(builder, plant, models.parts, scenario.sleep, periodic=False)

    _export_plant_ports(builder, plant, scene_graph)
    visualizer = _add_visualizer(builder, scene_graph, meshcat)

    diagram = builder.Build()
    diagram.set_name("station")
    return Station(
        scenario=scenario,
        diagram=diagram,
        plant=plant,
        scene_graph=scene_graph,
        arms=models.arms,
        cameras=cameras,
        parts=models.parts,
        pool=models.pool,
        meshcat=meshcat,
        visualizer=visualizer,
        conveyor=belt,
        break_beam=beam,
        grippers=grippers,
        bin_anchors=models.bin_anchors,
        rest_clock=rest_clock,
        models=models.described,
        depth_cameras=depth_cameras,
        joint_controllers=joint_controllers,
    )


def _add_visualizer(
    builder: DiagramBuilder, scene_graph: SceneGraph, meshcat: Optional[Meshcat]
) -> Optional[MeshcatVisualizer]:
    """Meshcat's view of the illustration geometry (none without ``meshcat``)."""
    if meshcat is None:
        return None
    return MeshcatVisualizer.AddToBuilder(
        builder, scene_graph, meshcat, MeshcatVisualizerParams(role=Role.kIllustration)
    )


def _add_cameras(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    scenario: Scenario,
    models: CellModels,
    meshcat: Optional[Meshcat],
) -> tuple[dict[str, LogicalCamera], dict[str, DepthCamera]]:
    """The logical cameras (each blind to its own model and the floor), their
    ``<camera>.image`` ports and the RGB-D views of those with ``rgbd``; then the camera
    and depth sensors of the scenario's models (:mod:`omtp_drake.cell.depth_camera`)."""
    cameras: dict[str, LogicalCamera] = {}
    for cam in scenario.cameras:
        # (what a student hung on the camera is part of its model: blind to it too)
        frame = f"{cam.name}_frame"
        hung = [plant.GetModelInstanceByName(m.name) for m in scenario.models if m.parent == frame]
        cameras[cam.name] = add_logical_camera(
            builder,
            plant,
            scene_graph,
            plant.GetFrameByName(f"{cam.name}_frame"),
            cam,
            exclude=[models.cameras[cam.name], models.floor, *hung],
            seed=scenario.seed,
        )
        builder.ExportOutput(cameras[cam.name].image_output_port(), f"{cam.name}.image")
        if cam.rgbd:
            _add_rgbd_view(builder, plant, scene_graph, cameras[cam.name])
    depth_cameras = add_model_cameras(
        builder, plant, scene_graph, models.described, scenario.models, seed=scenario.seed, meshcat=meshcat
    )
    return cameras, depth_cameras


def _export_plant_ports(builder: DiagramBuilder, plant: MultibodyPlant, scene_graph: SceneGraph) -> None:
    """The plant's and SceneGraph's outputs the station exports as they are."""
    builder.ExportOutput(plant.get_body_poses_output_port(), "body_poses")
    builder.ExportOutput(plant.get_contact_results_output_port(), "contact_results")
    builder.ExportOutput(plant.get_state_output_port(), "plant_state")
    builder.ExportOutput(scene_graph.get_query_output_port(), "query_object")


def _add_rgbd_view(
    builder: DiagramBuilder, plant: MultibodyPlant, scene_graph: SceneGraph, camera: LogicalCamera
) -> None:
    """The RGB-D view of ``camera`` (the renderer comes with the first one) and its ports
    ``<camera>.color_image``, ``<camera>.depth_image`` (32F, m), ``<camera>.label_image``."""
    from omtp_drake.cell.rgbd import add_rgbd_view

    name = camera.get_name()
    sensor = add_rgbd_view(builder, plant, scene_graph, plant.GetFrameByName(f"{name}_frame"), camera.config)
    builder.ExportOutput(sensor.color_image_output_port(), f"{name}.color_image")
    builder.ExportOutput(sensor.depth_image_32F_output_port(), f"{name}.depth_image")
    builder.ExportOutput(sensor.label_image_output_port(), f"{name}.label_image")


def _declare_weld_constraints(
    plant: MultibodyPlant, scenario: Scenario, models: CellModels
) -> dict[str, SuctionConstraints]:
    """Weld-backend grippers: their run-time constraints must exist before Finalize."""
    constraints: dict[str, SuctionConstraints] = {}
    if not models.parts or scenario.suction.backend != "weld":
        return constraints
    first = next(iter(models.parts))
    placeholder = plant.GetBodyByName(first, models.parts[first])
    for name, handles in models.arms.items():
        if handles.gripper is not None:
            cup = plant.GetBodyByName(f"{handles.config.gripper}_cup", handles.gripper)
            constraints[name] = declare_suction_constraints(plant, cup, placeholder)
    return constraints


def _add_conveyor(
    builder: DiagramBuilder, plant: MultibodyPlant, scenario: Scenario, models: CellModels
) -> Optional[ConveyorBelt]:
    config = scenario.conveyor
    if models.conveyor is None or config is None:
        return None
    belt = builder.AddNamedSystem("conveyor", ConveyorBelt(config.power, stop_on_beam=config.stop_on_beam))
    builder.Connect(belt.desired_state_output_port(), plant.get_desired_state_input_port(models.conveyor))
    builder.ExportOutput(belt.power_output_port(), "conveyor.power")
    return belt


def _add_break_beam(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scenario: Scenario,
    models: CellModels,
    belt: Optional[ConveyorBelt],
) -> Optional[BreakBeam]:
    if not scenario.break_beam:
        return None
    part_bodies = [plant.GetBodyByName(n, i) for n, i in models.parts.items()]
    boxes = [scenario.part_box(n) for n in models.parts]
    beam = builder.AddNamedSystem(
        "break_beam", BreakBeam(plant, plant.GetFrameByName("break_beam_optical_link"), part_bodies, boxes)
    )
    builder.Connect(plant.get_state_output_port(), beam.plant_state_input_port())
    builder.ExportOutput(beam.state_output_port(), "break_beam.state")
    if belt is not None:
        builder.Connect(beam.state_output_port(), belt.beam_input_port())
    return beam


def _add_grippers(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scenario: Scenario,
    models: CellModels,
    constraints: dict[str, SuctionConstraints],
    controlled: Collection[str],
) -> dict[str, SuctionGripper]:
    """The vacuum grippers (only when there are parts to grip)."""
    grippers: dict[str, SuctionGripper] = {}
    if not models.parts:
        return grippers
    part_bodies = [plant.GetBodyByName(n, i) for n, i in models.parts.items()]
    for name, handles in models.arms.items():
        if handles.gripper is None:
            continue
        cup = plant.GetBodyByName(f"{handles.config.gripper}_cup", handles.gripper)
        suction = suction_name(handles.config)
        grippers[name] = add_suction_gripper(
            builder,
            plant,
            cup,
            part_bodies,
            scenario.suction,
            suction,
            constraints.get(name),
            _gripper_polling(scenario, name, plant.time_step()) if name in controlled else None,
        )
        builder.ExportInput(grippers[name].command_input_port(), f"{suction}.command")
        builder.ExportOutput(grippers[name].state_output_port(), f"{suction}.state")
    connect_spatial_forces(builder, plant, list(grippers.values()))
    return grippers


def _gripper_polling(scenario: Scenario, robot: str, time_step: float) -> CommandPolling:
    """How the gripper of ``robot``, whose command a controller of the diagram writes,
    polls it. The task's controller writes it at ``task.update_rate_hz``, so the
    gripper looks one plant step after each update (when it would see the change at
    every step), and its checks, a multiple of that period apart, fall on those looks;
    if they do not (or for another controller), at every step. A gripper commanded by
    services (a script, ROS) never looks by itself; the runtime applies its rule when
    the command changes and when a check is due
    (:class:`omtp_drake.sim.gripper_events.GripperEvents`)."""
    task = scenario.task
    if task is None or task.robot != robot:
        return EVERY_STEP
    period = 1.0 / task.update_rate_hz
    checks = (1.0 / scenario.suction.check_rate_hz) / period
    if abs(checks - round(checks)) > 1e-6 or round(checks) < 1:
        return EVERY_STEP
    return CommandPolling(period, time_step)
