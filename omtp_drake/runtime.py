"""The runtime: one object that owns the simulator and makes the world edits.

Some edits cannot happen inside a Drake diagram (a system may not write
another system's Context): spawning and disposing of parts, the grippers'
weld constraints, shifting the belt surface back. :class:`FactoryRuntime`
advances the simulator in ticks of a fixed period (default 50 ms of
simulated time) and applies them between ticks. It offers the course's
services as methods: spawn a part, set the conveyor power, enable or disable a
gripper, read a gripper's state, read a camera, read the ledger.

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
from dataclasses import replace
from typing import Callable, Optional

from pydrake.geometry import Meshcat
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, DiagramBuilder

from omtp_drake import arms
from omtp_drake.errors import ConfigError, SimulationError, UnknownNameError
from omtp_drake.conveyor import WRAP_TRAVEL
from omtp_drake.logical_camera import LogicalCameraImage
from omtp_drake.parts import (Ledger, PartBook, SpawnerConfig, return_to_pool, spawn_pose,
                              take_from_pool)
from omtp_drake.scenario import Scenario, load_scenario
from omtp_drake.station import Station, build_station
from omtp_drake.suction import sync_weld

_log = logging.getLogger(__name__)

#: The drawn belt: x within 0.3 of its centre line, y in [-5, 5], top at 0.92.
_BELT_X, _BELT_HALF_WIDTH, _BELT_Y, _BELT_TOP = 1.2, 0.3, (-5.0, 5.0), 0.92
#: The deletion wall checks for contact at 5 Hz.
_DISPOSAL_PERIOD = 0.2

#: A function that adds systems around the station (controllers...) before the
#: diagram is built; it connects whatever station inputs it drives.
Extension = Callable[[DiagramBuilder, Station], None]


class FactoryRuntime:
    """Owns the diagram, its Context and the Simulator of one scenario."""

    def __init__(
        self,
        scenario: Scenario | str,
        *,
        meshcat: Optional[Meshcat] = None,
        tick: float = 0.05,
        extend: Optional[Extension] = None,
    ):
        if not isinstance(scenario, Scenario):
            scenario = load_scenario(scenario)
        if not 0 < tick <= 1.0:
            raise ConfigError(f"tick must be in (0, 1] s, got {tick}")
        self.scenario = scenario
        self.tick = tick
        self.station = build_station(scenario, meshcat=meshcat)
        builder = DiagramBuilder()
        builder.AddSystem(self.station.diagram)
        if extend is not None:
            extend(builder, self.station)
        free_inputs = [self.station.diagram.get_input_port(i)
                       for i in range(self.station.diagram.num_input_ports())
                       if not builder.IsConnectedOrExported(self.station.diagram.get_input_port(i))]
        self.diagram = builder.Build()
        self.diagram.set_name("factory")
        self.context = self.diagram.CreateDefaultContext()
        self._station_context = self.station.diagram.GetMyMutableContextFromRoot(self.context)
        self._plant_context = self.station.plant.GetMyMutableContextFromRoot(self.context)
        for name, handles in self.station.arms.items():
            q = arms.named_pose(handles.config.initial_pose, handles.config)
            self.station.set_arm_positions(self.context, name, q)
        for port in free_inputs:  # hold what nobody drives
            name = port.get_name()
            if name.endswith(".position"):
                robot = name.split(".")[0]
                port.FixValue(self._station_context, self.station.plant.GetPositions(
                    self._plant_context, self.station.arm(robot).arm))
            elif name.endswith(".command"):
                port.FixValue(self._station_context, [0.0])
        self._free_inputs = {p.get_name() for p in free_inputs}
        self.station.initialize_context(self.context)
        self.simulator = Simulator(self.diagram, self.context)
        self.simulator.Initialize()
        self._next_disposal = 0.0
        self._after_tick: list[Callable[[FactoryRuntime], None]] = []
        self._tick_actions()

    # ------------------------------------------------------------------ time

    @property
    def time(self) -> float:
        return self.context.get_time()

    def advance_to(self, t: float) -> None:
        """Simulates until time ``t``, applying world edits at every tick."""
        if t < self.time:
            raise SimulationError(f"cannot go back in time: now {self.time:.3f} s, asked {t:.3f} s")
        while self.time < t - 1e-12:
            k = math.floor(self.time / self.tick + 1e-9) + 1
            boundary = k * self.tick
            self.simulator.AdvanceTo(min(t, boundary))
            if abs(self.time - boundary) < 1e-9:
                self._tick_actions()

    def advance(self, dt: float) -> None:
        self.advance_to(self.time + dt)

    def on_tick(self, callback: Callable[[FactoryRuntime], None]) -> None:
        """Calls ``callback(runtime)`` after the world edits of every tick."""
        self._after_tick.append(callback)

    def _tick_actions(self) -> None:
        self._sync_suction()
        self._wrap_belt()
        if self.time >= self._next_disposal - 1e-9:
            self._dispose_touching_wall()
            self._next_disposal = self.time + _DISPOSAL_PERIOD
        self._auto_spawn()
        for callback in self._after_tick:
            callback(self)

    # ------------------------------------------------------------------ arms

    def hold_arm(self, name: str, q) -> None:
        """Puts arm ``name`` at rest at ``q`` and commands it to stay there.

        Only for an arm whose position command nobody drives (no controller).
        """
        handles = self.station.arm(name)
        port = f"{name}.position"
        if port not in self._free_inputs:
            raise SimulationError(f"{port} is driven by a controller; it cannot be held")
        self.station.set_arm_positions(self.context, name, q)
        self.station.diagram.GetInputPort(port).FixValue(
            self._station_context, self.station.plant.GetPositions(self._plant_context, handles.arm))

    # ------------------------------------------------------------------ grippers

    def _gripper(self, robot: str):
        self.station.suction_name(robot)  # the error lists the robots with grippers
        return self.station.grippers[robot]

    def enable_gripper(self, robot: str) -> None:
        """The course's ``/gripperN/control enable: true`` (when no controller drives it)."""
        self._command_gripper(robot, 1.0)

    def disable_gripper(self, robot: str) -> None:
        """Vacuum off: a held part is released at the next check (20 Hz) and falls."""
        self._command_gripper(robot, 0.0)

    def _command_gripper(self, robot: str, value: float) -> None:
        port = f"{self.station.suction_name(robot)}.command"
        if port not in self._free_inputs:
            raise SimulationError(f"{port} is driven by a controller; use a fault injection instead")
        self.station.diagram.GetInputPort(port).FixValue(self._station_context, [value])

    def gripper_state(self, robot: str):
        """The gripper's GripperState: ``enabled``, ``attached``, ``part``."""
        gripper = self._gripper(robot)
        return gripper.get_state(gripper.GetMyContextFromRoot(self.context))

    def fail_vacuum(self, robot: str, duration: float) -> None:
        """Fault injection: ``robot``'s vacuum fails now for ``duration`` s (a held
        part drops at the next check, ~50 ms), whatever its controller commands."""
        gripper = self._gripper(robot)
        gripper.fail_vacuum(gripper.GetMyMutableContextFromRoot(self.context), self.time + duration)

    def black_out_camera(self, camera: str, duration: float) -> None:
        """Fault injection: ``camera`` publishes no image for ``duration`` s."""
        if camera not in self.station.cameras:
            raise UnknownNameError("camera", camera, self.station.cameras)
        system = self.station.cameras[camera]
        system.black_out(system.GetMyMutableContextFromRoot(self.context), self.time + duration)

    def _sync_suction(self) -> None:
        for robot, constraints in self.station.suction_constraints.items():
            sync_weld(self.station.grippers[robot], constraints, self.station.plant, self.context)

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
            self._station_context)
        return bool(detected > 0.5), float(distance)

    def _wrap_belt(self) -> None:
        if self.station.conveyor is None:
            return
        joint = self.station.plant.GetJointByName("conveyor_belt_joint")
        q = joint.get_translation(self._plant_context)
        if abs(q) >= WRAP_TRAVEL:
            joint.set_translation(self._plant_context, math.fmod(q, WRAP_TRAVEL))

    # ------------------------------------------------------------------ cameras

    def camera_image(self, camera: str) -> LogicalCameraImage:
        """The latest image of a logical camera."""
        if camera not in self.station.cameras:
            raise UnknownNameError("camera", camera, self.station.cameras)
        return self.station.diagram.GetOutputPort(f"{camera}.image").Eval(self._station_context)

    # ------------------------------------------------------------------ parts

    def _manager_context(self) -> Context:
        manager = self._need(self.station.part_manager, "part pool")
        return manager.GetMyMutableContextFromRoot(self.context)

    def _book(self) -> PartBook:
        return self.station.part_manager.book(self._manager_context())

    def _set_book(self, book: PartBook) -> None:
        self.station.part_manager.set_book(self._manager_context(), book)

    def spawn_part(self, xyz: Optional[list[float]] = None, yaw: Optional[float] = None) -> str:
        """Spawns the next parked part; returns its name.

        Without ``xyz``/``yaw`` the scenario's spawner pose (plus its seeded
        variance) is used. With the spawner's ``one_at_a_time`` (the course's
        ``spawn_object_once``), spawning while another part is loose in the
        world (not in a bin) raises SimulationError.
        """
        spawner = self.station.scenario.spawner
        if spawner is None and xyz is None:
            raise ConfigError("this scenario has no spawner: give the spawn position xyz")
        if spawner is not None and spawner.one_at_a_time:
            loose = self._loose_parts()
            if loose:
                raise SimulationError(
                    f"one part at a time: {', '.join(loose)} is still in the world")
        book, index = take_from_pool(self._book(), self.time)
        name = book.parts[index].name
        X_WP = (spawn_pose(spawner, self.scenario.seed, book.spawn_count - 1, xyz, yaw)
                if spawner is not None else
                spawn_pose(SpawnerConfig(), self.scenario.seed, 0, xyz, yaw or 0.0))
        plant = self.station.plant
        body = plant.GetBodyByName(name, self.station.parts[name])
        self.station.unpark(self._plant_context, name)
        plant.SetFreeBodyPose(self._plant_context, body, X_WP)
        plant.SetFreeBodySpatialVelocity(self._plant_context, body, SpatialVelocity.Zero())
        self._set_book(book)
        _log.info("t=%.2f spawned %s at %s", self.time, name, X_WP.translation())
        return name

    def remove_part(self, name: str) -> None:
        """Disposes of a spawned part now (as the deletion wall does)."""
        book = self._book()
        names = [r.name for r in book.parts if r.state == "in_world"]
        if name not in names:
            raise UnknownNameError("part in the world", name, names)
        self._dispose(book, [r.name for r in book.parts].index(name))

    def _dispose(self, book: PartBook, index: int) -> None:
        name = book.parts[index].name
        self.station.park(self._plant_context, name)
        self._set_book(return_to_pool(book, index, self.time))
        _log.info("t=%.2f disposed of %s", self.time, name)

    def _auto_spawn(self) -> None:
        spawner = self.station.scenario.spawner
        if spawner is None or spawner.period <= 0:
            return
        book = self._book()
        if self.time < book.next_auto_spawn - 1e-9:
            return
        if spawner.max_parts and book.auto_spawns >= spawner.max_parts:
            return
        if spawner.one_at_a_time and self._loose_parts():
            return  # documented wait: the spawn happens at the first tick the world is clear
        if not book.queue:
            raise SimulationError(
                f"t={self.time:.2f}: the spawner found no parked part; raise part_pool "
                f"(now {len(book.parts)})")
        self.spawn_part()
        book = self._book()
        self._set_book(replace(book, auto_spawns=book.auto_spawns + 1,
                               next_auto_spawn=self.time + spawner.period))

    def _dispose_touching_wall(self) -> None:
        if not self.scenario.deletion_wall or not self.station.pool:
            return
        plant = self.station.plant
        wall = int(plant.GetBodyByName("deletion_wall").index())
        by_body = {int(plant.GetBodyByName(n, self.station.parts[n]).index()): n
                   for n in self.station.pool}
        results = self.station.diagram.GetOutputPort("contact_results").Eval(self._station_context)
        touching = set()
        for i in range(results.num_point_pair_contacts()):
            info = results.point_pair_contact_info(i)
            a, b = int(info.bodyA_index()), int(info.bodyB_index())
            if wall in (a, b):
                other = b if a == wall else a
                if other in by_body:
                    touching.add(by_body[other])
        for name in sorted(touching):
            book = self._book()
            self._dispose(book, [r.name for r in book.parts].index(name))

    def part_pose(self, name: str) -> RigidTransform:
        """Ground-truth world pose of a part (for tests and plots, not for controllers)."""
        if name not in self.station.parts:
            raise UnknownNameError("part", name, self.station.parts)
        plant = self.station.plant
        return plant.EvalBodyPoseInWorld(
            self._plant_context, plant.GetBodyByName(name, self.station.parts[name]))

    def parts_in_world(self) -> list[str]:
        """Placed parts and spawned parts not disposed of."""
        book = self._book()
        pooled = {r.name for r in book.parts if r.state == "parked"}
        return [n for n in self.station.parts if n not in pooled]

    def _where(self, name: str, held: dict[str, str]) -> tuple[str, str]:
        """(state, detail) of a part in the world, from its pose and ``held``
        (robot -> part, from :meth:`_held`)."""
        for robot, part in held.items():
            if part == name:
                return "held", robot
        p = self.part_pose(name).translation()
        for b in self.scenario.bins:
            if b.contains(p):
                return "in_bin", b.name
        if (self.station.conveyor is not None and abs(p[0] - _BELT_X) <= _BELT_HALF_WIDTH
                and _BELT_Y[0] <= p[1] <= _BELT_Y[1] and p[2] > _BELT_TOP):
            return "on_belt", ""
        return "on_floor", ""

    def _held(self) -> dict[str, str]:
        """robot -> name of the part its gripper holds."""
        held = {}
        for robot in self.station.grippers:
            state = self.gripper_state(robot)
            if state.attached:
                held[robot] = state.part
        return held

    def _loose_parts(self) -> list[str]:
        held = self._held()
        return [n for n in self.parts_in_world() if self._where(n, held)[0] != "in_bin"]

    def ledger(self) -> Ledger:
        """Where every spawned or placed part is now."""
        book = self._book()
        held = {r: 0 for r in self.station.arms}
        in_bin = {b.name: 0 for b in self.scenario.bins}
        counts = {"on_belt": 0, "on_floor": 0}
        parts = {}
        held_parts = self._held()
        for name in self.parts_in_world():
            state, detail = self._where(name, held_parts)
            parts[name] = f"{state}:{detail}" if detail else state
            if state == "held":
                held[detail] += 1
            elif state == "in_bin":
                in_bin[detail] += 1
            else:
                counts[state] += 1
        placed = len(self.station.parts) - len(self.station.pool)
        return Ledger(time=self.time, spawned=book.spawn_count + placed,
                      parked=sum(r.state == "parked" for r in book.parts),
                      on_belt=counts["on_belt"], on_floor=counts["on_floor"], held=held,
                      in_bin=in_bin, disposed=book.dispose_count, parts=parts)

    # ------------------------------------------------------------------ helpers

    @staticmethod
    def _need(thing, what: str):
        if thing is None:
            raise ConfigError(f"this scenario has no {what}")
        return thing

