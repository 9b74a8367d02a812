"""The runtime: a scenario's cell, ready to run, and the course's services on it.

:class:`FactoryRuntime` builds the station (and whatever ``extend`` adds around
it, e.g. a controller), initialises the Context, and runs it with the
:class:`~omtp_drake.sim.driver.Driver` (the world edits between advances). Its
methods are the course's services: spawn or remove a part, set the conveyor
power, enable or disable a gripper, read a gripper, a camera, the break beam,
the ledger; and fault injection for tests (vacuum failure, camera blackout, a
blocked arm, a moved bin). Every method checks its arguments and raises an
:mod:`omtp_drake.errors` error naming the bad value and the valid choices.

Everything depends only on simulated time and the scenario's seed, so the same
scenario and seed give the same result.

Example::

    rt = FactoryRuntime("lecture7_conveyor")
    rt.advance_to(8.0)
    image = rt.camera_image("logical_camera_1")   # the part the beam stopped
    ledger = rt.ledger()
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from typing import Optional

import numpy as np
from pydrake.geometry import Meshcat
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.framework import Context, DiagramBuilder

from omtp_drake.cell import arms
from omtp_drake.cell.lifetime import release
from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.station import Station, build_station
from omtp_drake.cell.suction import GripperState
from omtp_drake.errors import ConfigError, SimulationError, UnknownNameError, check_duration, check_vector
from omtp_drake.scenario import Scenario, as_scenario
from omtp_drake.sim.driver import AutoSpawner, Driver, world_edits
from omtp_drake.sim.faults import FaultInjector
from omtp_drake.sim.gripper_events import GripperEvents
from omtp_drake.sim.parts import PartServices
from omtp_drake.sim.pool import PartPool

_log = logging.getLogger(__name__)

#: A function that adds systems around the station (controllers...) before the
#: diagram is built; it connects whatever station inputs it drives.
Extension = Callable[[DiagramBuilder, Station], None]


class ArmBlock:
    """Fault injection: arms whose joints are locked (blocked) until a time.
    A world edit with events of its own: it unlocks each arm at the first plant step
    at or after its time (the driver need not stop otherwise)."""

    period = math.inf

    def __init__(self, station: Station):
        self._station = station
        self._step = station.plant.time_step()
        self.until: dict[str, float] = {}

    def block(self, root_context: Context, robot: str, until: float) -> None:
        self._station.set_arm_locked(root_context, robot, True)
        self.until[robot] = until

    def next_time(self, root_context: Context) -> float:
        """The plant step at or after the first arm's time is up (inf: none blocked)."""
        if not self.until:
            return math.inf
        return math.ceil(min(self.until.values()) / self._step - 1e-6) * self._step

    def before_advance(self, root_context: Context) -> None:
        pass

    def __call__(self, root_context: Context) -> None:
        for robot, until in list(self.until.items()):
            if root_context.get_time() >= until - 1e-9:
                self._station.set_arm_locked(root_context, robot, False)
                self._station.clear_servo_integral(root_context, robot)
                del self.until[robot]


class FactoryRuntime(PartServices):
    """A scenario's cell, its Context and driver, and the course's services (the
    part services are those of :class:`~omtp_drake.sim.parts.PartServices`).

    ``extend`` adds systems around the station; ``controlled`` names the robots whose
    gripper command they write (their grippers poll it; the others take the
    services' commands as events, and one written by a system not named here is
    refused)."""

    def __init__(
        self,
        scenario: Scenario | str,
        *,
        meshcat: Optional[Meshcat] = None,
        tick: float = 0.05,
        extend: Optional[Extension] = None,
        auto_spawn: bool = True,
        controlled: Sequence[str] = (),
    ):
        scenario = as_scenario(scenario)
        tick = check_duration("tick", tick)
        if tick > 1.0:
            raise ConfigError(f"tick must be in (0, 1] s, got {tick}")
        self.scenario = scenario
        self.tick = tick
        self.station = build_station(scenario, meshcat=meshcat, controlled=controlled)
        builder = DiagramBuilder()
        builder.AddSystem(self.station.diagram)
        if extend is not None:
            extend(builder, self.station)
        free = [
            self.station.diagram.get_input_port(i)
            for i in range(self.station.diagram.num_input_ports())
            if not builder.IsConnectedOrExported(self.station.diagram.get_input_port(i))
        ]
        self.diagram = builder.Build()
        self.diagram.set_name("factory")
        self._free_inputs = {p.get_name() for p in free}
        self.context = self.diagram.CreateDefaultContext()
        self.station.initialize_context(self.context, hold=free)
        self._station_context = self.station.diagram.GetMyMutableContextFromRoot(self.context)
        self._plant_context = self.station.plant.GetMyMutableContextFromRoot(self.context)
        self.pool = PartPool(self.station)
        edits = world_edits(self.station, self.pool)
        self._arm_block = ArmBlock(self.station)
        edits.append(self._arm_block)
        self._gripper_events = next((e for e in edits if isinstance(e, GripperEvents)), None)
        if self._gripper_events is not None:
            commands = {r: f"{self.station.suction_name(r)}.command" for r in self.station.grippers}
            self._gripper_events.serve(r for r, port in commands.items() if port in self._free_inputs)
            self._gripper_events.check_driven(
                r for r, port in commands.items() if port not in self._free_inputs
            )
        spawner = next((e for e in edits if isinstance(e, AutoSpawner)), None)
        if spawner is not None:
            spawner.enabled = auto_spawn
        self._spawner = spawner
        self.driver = Driver(self.diagram, self.context, edits)
        #: The scenario's faults as they strike (None when it declares none).
        self.faults = FaultInjector(self, scenario.faults) if scenario.faults else None
        if self.faults is not None:
            self.driver.every(self.faults.period, self.faults)
        self._closed = False

    def close(self) -> None:
        """Frees the cell: its diagram, plant, Contexts and our systems (see
        :mod:`omtp_drake.cell.lifetime`; without it a built cell stays in memory for
        the life of the process). Afterwards the runtime refuses to advance or to
        take images. Closing twice is harmless."""
        if not self._closed:
            self._closed = True
            release(self.diagram)

    def _check_open(self) -> None:
        if self._closed:
            raise SimulationError(f"this {self.scenario.name!r} cell is closed; build a new one to run again")

    # ------------------------------------------------------------------ time

    @property
    def time(self) -> float:
        return self.context.get_time()

    @property
    def simulator(self):
        return self.driver.simulator

    def advance_to(self, t: float) -> None:
        """Simulates until time ``t`` (the world edits happen when due)."""
        self._check_open()
        self.driver.advance_to(float(t))

    def advance(self, dt: float) -> None:
        """Simulates ``dt`` seconds more."""
        dt = float(dt)
        if not (dt >= 0 and math.isfinite(dt)):
            raise ConfigError(f"advance needs a finite time >= 0 s, got {dt}")
        self.advance_to(self.time + dt)

    def on_tick(self, callback: Callable[[FactoryRuntime], None]) -> None:
        """Calls ``callback(runtime)`` every ``tick`` seconds (after the world edits)."""
        self.driver.every(self.tick, lambda: callback(self))

    @property
    def auto_spawn(self) -> bool:
        """Whether the scenario's spawner spawns parts by itself (False without one)."""
        return self._spawner is not None and self._spawner.enabled

    @auto_spawn.setter
    def auto_spawn(self, enabled: bool) -> None:
        if self._spawner is None:
            if enabled:
                raise ConfigError(f"scenario {self.scenario.name!r} has no spawner to switch on")
            return
        self._spawner.enabled = bool(enabled)

    # ------------------------------------------------------------------ arms

    def hold_arm(self, name: str, q) -> None:
        """Puts arm ``name`` at rest at ``q`` and commands it to stay there (a
        teleport: only for an arm whose position command nobody drives, e.g. to
        set up a scene; a held part stays held)."""
        handles = self.station.arm(name)
        q = arms.check_joint_positions(q, handles.config)
        port = f"{name}.position"
        if port not in self._free_inputs:
            raise SimulationError(f"{port} is driven by a controller; it cannot be held")
        self.station.set_arm_positions(self.context, name, q)
        self.station.diagram.GetInputPort(port).FixValue(self._station_context, q)

    def joint_positions(self, name: str) -> np.ndarray:
        """The measured joint positions of arm ``name`` (pan ... wrist 3)."""
        return self.station.plant.GetPositions(self._plant_context, self.station.arm(name).arm)

    def block_arm(self, robot: str, duration: float) -> None:
        """Fault injection: ``robot``'s joints are blocked (locked where they are)
        for ``duration`` s, whatever its servo commands."""
        self.station.arm(robot)
        duration = check_duration("block_arm duration", duration)
        self._arm_block.block(self.context, robot, self.time + duration)

    # ------------------------------------------------------------------ grippers

    def _gripper(self, robot: str):
        self.station.suction_name(robot)  # the error lists the robots with grippers
        return self.station.grippers[robot]

    def enable_gripper(self, robot: str) -> None:
        """The course's ``/gripperN/control enable: true`` (when no controller drives it)."""
        self._command_gripper(robot, 1.0)

    def disable_gripper(self, robot: str) -> None:
        """Vacuum off: a held part is released at the plant step at or after now, its
        constraints one step later, and it falls."""
        self._command_gripper(robot, 0.0)

    def _command_gripper(self, robot: str, value: float) -> None:
        port = f"{self.station.suction_name(robot)}.command"
        if port not in self._free_inputs:
            raise SimulationError(f"{port} is driven by a controller; use a fault injection instead")
        self.station.diagram.GetInputPort(port).FixValue(self._station_context, [value])
        self._need(self._gripper_events, "gripper").command(self.context, robot)

    def gripper_state(self, robot: str) -> GripperState:
        """The gripper's GripperState: ``enabled``, ``attached``, ``part``."""
        gripper = self._gripper(robot)
        return gripper.get_state(gripper.GetMyContextFromRoot(self.context))

    def fail_vacuum(self, robot: str, duration: float) -> None:
        """Fault injection: ``robot``'s vacuum fails now for ``duration`` s (a held
        part drops at the next plant step), whatever its controller commands."""
        gripper = self._gripper(robot)
        duration = check_duration("fail_vacuum duration", duration)
        gripper.fail_vacuum(gripper.GetMyMutableContextFromRoot(self.context), self.time + duration)
        self._need(self._gripper_events, "gripper").fault(self.context, robot, self.time + duration)

    def black_out_camera(self, camera: str, duration: float) -> None:
        """Fault injection: ``camera`` publishes no image for ``duration`` s."""
        system = self._camera(camera)
        duration = check_duration("black_out_camera duration", duration)
        system.black_out(system.GetMyMutableContextFromRoot(self.context), self.time + duration)

    # ------------------------------------------------------------------ bins

    def bin_pose(self, name: str) -> RigidTransform:
        """``X_WB``: where bin ``name``'s base is now."""
        return self.station.bin_pose(self.context, name)

    def move_bin(self, name: str, xyz: Sequence[float], yaw: float = 0.0) -> None:
        """Fault injection: bin ``name`` jumps to ``xyz`` (its base, on the floor)
        turned ``yaw`` about world z; parts in it move with it."""
        X_old = self.bin_pose(name)
        p = check_vector("move_bin xyz", xyz)
        if not math.isfinite(yaw):
            raise ConfigError(f"move_bin yaw must be finite, got {yaw!r}")
        X_new = RigidTransform(RollPitchYaw(0.0, 0.0, yaw), p)
        X_move = X_new @ X_old.inverse()
        plant = self.station.plant
        carried = [n for n, where in self.ledger().parts.items() if where == f"in_bin:{name}"]
        self.station.move_bin(self.context, name, X_new)
        for part in carried:
            body = plant.GetBodyByName(part, self.station.parts[part])
            plant.SetFreeBodyPose(self._plant_context, body, X_move @ self.part_pose(part))

    # ------------------------------------------------------------------ conveyor

    def set_conveyor_power(self, power: float) -> None:
        """The course's conveyor service: power in [0, 100] percent."""
        belt = self._need(self.station.conveyor, "conveyor")
        belt.set_power(belt.GetMyMutableContextFromRoot(self.context), power)

    def conveyor_power(self) -> float:
        belt = self._need(self.station.conveyor, "conveyor")
        return belt.power(belt.GetMyContextFromRoot(self.context))

    def break_beam(self) -> tuple[bool, float]:
        """(object_detected, range of the nearest hit) as last sampled (10 Hz)."""
        self._need(self.station.break_beam, "break beam")
        detected, distance = self.station.diagram.GetOutputPort("break_beam.state").Eval(
            self._station_context
        )
        return bool(detected > 0.5), float(distance)

    # ------------------------------------------------------------------ cameras

    def _camera(self, camera: str):
        if camera not in self.station.cameras:
            raise UnknownNameError("camera", camera, self.station.cameras, closest=True)
        return self.station.cameras[camera]

    def sample_cameras(self) -> None:
        """Every logical camera takes its image now, at the current time (as it does at
        its sample times); nothing else changes. For reports of the state at a time T
        (an advance to T stops before the samples due at T are taken)."""
        self._check_open()
        for camera in self.station.cameras.values():
            camera.ExecuteForcedEvents(camera.GetMyMutableContextFromRoot(self.context))

    def camera_image(self, camera: str) -> LogicalCameraImage:
        """The latest image of a logical camera."""
        self._camera(camera)
        return self.station.diagram.GetOutputPort(f"{camera}.image").Eval(self._station_context)

    # ------------------------------------------------------------------ helpers

    @staticmethod
    def _need(thing, what: str):
        if thing is None:
            raise ConfigError(f"this scenario has no {what}")
        return thing


def runtime_at(
    scenario: Scenario | str,
    time: float,
    poses: Optional[dict[str, str]] = None,
    camera: Optional[str] = None,
) -> FactoryRuntime:
    """The scenario run (spawner included) from rest to ``time``, each arm held at a
    named pose (``poses``: robot -> pose, default Home) or, without ``poses``, at its
    initial pose, with the cameras' images of ``time``. An unknown ``camera`` or robot
    in ``poses`` raises :class:`UnknownNameError` before anything is simulated."""
    runtime = FactoryRuntime(scenario)
    station = runtime.station
    if camera is not None and camera not in station.cameras:
        raise UnknownNameError("camera", camera, station.cameras)
    if poses is not None:
        for robot in poses:
            station.arm(robot)  # unknown robot: one clear error
        for name, h in station.arms.items():
            runtime.hold_arm(name, arms.named_pose(poses.get(name, "Home"), h.config))
    runtime.advance_to(time)
    # The images at `time` (not the state one plant step later: the plant stays at `time`).
    runtime.sample_cameras()
    return runtime
