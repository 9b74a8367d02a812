"""The driver: one way to run the cell.

Some changes to the world are not a system's to make, because a system may
not write another system's Context (Drake's rule): spawning and disposing of
parts, making a weld gripper's constraints, shifting the belt surface back,
moving a bin. Each is a small :class:`WorldEdit` with a period; the
:class:`Driver` owns the Simulator, advances it to the next time an edit (or a
callback) is due, and applies the edits due there, between advances.

Everything depends only on simulated time and the scenario's seed, so the same
scenario and seed give the same run.

Example (what :class:`omtp_drake.sim.runtime.FactoryRuntime` does)::

    context = diagram.CreateDefaultContext()
    station.initialize_context(context, hold=free_station_inputs)
    pool = PartPool(station)
    driver = Driver(diagram, context, world_edits(station, pool))
    driver.advance_to(10.0)
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional, Protocol, runtime_checkable

from pydrake.math import RigidTransform
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, Diagram

from omtp_drake.cell.conveyor import WRAP_TRAVEL
from omtp_drake.cell.gazebo_models import gazebo_models
from omtp_drake.cell.parts import spawn_pose
from omtp_drake.errors import ConfigError, SimulationError, check_duration
from omtp_drake.scenario import SpawnerConfig
from omtp_drake.scenario.conveyor_spawner import WORLD_FRAMES, draw, kind_of
from omtp_drake.sim.deletion_wall import DeletionWall
from omtp_drake.sim.gripper_events import GripperEvents
from omtp_drake.sim.heap import tune_heap
from omtp_drake.sim.joint_pose_trajectory import joint_pose_trajectories
from omtp_drake.sim.ledger import bin_of, held_parts, locate
from omtp_drake.sim.part_sleep import PartSleep
from omtp_drake.sim.pool import PartPool

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

_log = logging.getLogger(__name__)

#: Times closer than this (s) are the same time.
_EPS = 1e-9
#: The spawner looks whether a spawn is due at 20 Hz.
SPAWN_CHECK_PERIOD = 0.05
#: The belt surface travels at most 0.2 m/s: shifting it back every second
#: keeps it within WRAP_TRAVEL.
BELT_WRAP_PERIOD = 1.0


class WorldEdit(Protocol):
    """A change to the Context that no system may make, applied between advances.

    The driver applies it at every multiple of ``period`` (s of simulated time),
    before the events due at that time are handled.
    """

    @property
    def period(self) -> float: ...

    def __call__(self, root_context: Context) -> None: ...


@runtime_checkable
class EventSource(Protocol):
    """A world edit with events of its own besides its period: the driver also stops
    at :meth:`next_time` (and applies the edit there), and calls :meth:`before_advance`
    right before each advance (after the edits and callbacks due at that time)."""

    def next_time(self, root_context: Context) -> float: ...

    def before_advance(self, root_context: Context) -> None: ...


class BeltWrap:
    """Shifts the belt's moving contact surface back along its own length (no
    contact changes) so it never runs out of travel."""

    period = BELT_WRAP_PERIOD

    def __init__(self, station: Station):
        self._plant = station.plant
        self._joint = station.plant.GetJointByName("conveyor_belt_joint")

    def __call__(self, root_context: Context) -> None:
        plant_context = self._plant.GetMyMutableContextFromRoot(root_context)
        q = self._joint.get_translation(plant_context)
        if abs(q) >= WRAP_TRAVEL:
            self._joint.set_translation(plant_context, math.fmod(q, WRAP_TRAVEL))


@dataclass
class AutoSpawner:
    """The scenario's spawner: a part every ``spawner.period`` seconds from
    ``spawner.start_time``; with ``one_at_a_time`` only when no other part is
    loose (the spawn happens at the first check the world is clear); at most
    ``spawner.max_parts`` (0: no limit). ``enabled`` switches it off (a
    student's own script spawning parts itself).

    It checks at the multiples of ``SPAWN_CHECK_PERIOD`` (an
    :class:`EventSource` with no period of its own), and only at those where a spawn
    may happen: from the first at or after the spawn is due, and not while a loose
    part it found at its last check sleeps (it cannot move, so the world cannot be
    clear, until the driver wakes it or it is disposed of or written off, all between
    advances)."""

    station: Station
    pool: PartPool
    enabled: bool = True
    #: Automatic spawns so far and the time of the next one.
    spawned: int = 0
    next_spawn: float = field(default=math.nan)
    #: A loose sleeping part the last check found (the world is not clear while it
    #: sleeps where it was); "" when none.
    blocker: str = ""
    #: No stops besides its checks' (see :meth:`next_time`).
    period: float = math.inf

    def _done(self) -> bool:
        spawner = self.station.scenario.spawner
        return spawner is None or spawner.period <= 0 or self._enough(spawner) or not self.enabled

    def next_time(self, root_context: Context) -> float:
        """The next check: the first multiple of SPAWN_CHECK_PERIOD after now and at or
        after the spawn is due; inf once it is off or done, or while the blocker sleeps."""
        if self._done():
            return math.inf
        if self.blocker and self._still_blocked(root_context):
            return math.inf
        now = root_context.get_time()
        k = math.floor(now / SPAWN_CHECK_PERIOD + _EPS) + 1  # (the driver's next multiple)
        due = self.next_spawn + self._delay() - _EPS
        if k * SPAWN_CHECK_PERIOD < due:
            k = max(k, math.ceil(due / SPAWN_CHECK_PERIOD - _EPS))
            while k * SPAWN_CHECK_PERIOD < due:
                k += 1
        return k * SPAWN_CHECK_PERIOD

    def before_advance(self, root_context: Context) -> None:
        pass

    def _still_blocked(self, root_context: Context) -> bool:
        """Whether the blocker still sleeps where it was (asleep, not written off)."""
        if self.blocker in self.pool.written_off:
            return False
        plant_context = self.station.plant.GetMyContextFromRoot(root_context)
        return self.station.part_states.is_asleep(plant_context, self.blocker)  # (disposed: parked)

    def _delay(self) -> float:
        """The course's plugin waits its drawn spawn_timing_variance after the tick."""
        spawner = self.station.scenario.spawner
        if spawner is None or not spawner.objects:
            return 0.0
        return draw(spawner, self.station.scenario.seed, self.pool.spawn_count).delay

    def _enough(self, spawner: SpawnerConfig) -> bool:
        """max_parts spawned (parts written off do not count: they are replaced)."""
        kept = self.spawned - len(self.pool.written_off)
        return bool(spawner.max_parts and kept >= spawner.max_parts)

    def __post_init__(self) -> None:
        spawner = self.station.scenario.spawner
        if math.isnan(self.next_spawn):
            self.next_spawn = spawner.start_time if spawner is not None else math.inf

    def __call__(self, root_context: Context) -> None:
        self.blocker = ""
        spawner = self.station.scenario.spawner
        if spawner is None or self._done():
            return
        t = root_context.get_time()
        delay = self._delay()
        if t < self.next_spawn + delay - _EPS:
            return
        if spawner.one_at_a_time:
            loose, held = _first_loose(self.station, root_context, self.pool)
            if loose:  # waits for a clear world
                plant_context = self.station.plant.GetMyContextFromRoot(root_context)
                if not held and self.station.part_states.is_asleep(plant_context, loose):
                    self.blocker = loose
                return
        if not self.pool.queue(root_context):
            raise SimulationError(
                f"t={t:.2f}: the spawner found no parked part; raise part_pool (now {len(self.station.pool)})"
            )
        spawn(self.station, root_context, self.pool)
        self.spawned += 1
        # The next tick one period after this one (its callback not before this one's end).
        self.next_spawn = max(t - delay + spawner.period, t)


def loose_parts(station: Station, root_context: Context, pool: PartPool) -> list[str]:
    """Parts in the world that are not in a bin (held ones included), but for those
    written off (lost where nobody can pick them)."""
    held = held_parts(station, root_context)
    return [
        n
        for n in pool.in_world(root_context)
        if n not in pool.written_off and locate(station, root_context, n, held)[0] != "in_bin"
    ]


def _first_loose(station: Station, root_context: Context, pool: PartPool) -> tuple[str, bool]:
    """A part :func:`loose_parts` has ("" when none), and whether it is held: a held part
    (a held part over a bin counts as loose; the grippers' states are read first, the
    cheapest test), else a part out of the bins (the newest first: the older ones are
    mostly in a bin, the newest usually loose)."""
    held = held_parts(station, root_context)
    if held:
        return next(iter(held.values())), True
    written_off = pool.written_off
    for n in reversed(pool.in_world(root_context)):
        if n not in written_off and bin_of(station, root_context, n) is None:
            return n, False
    return "", False


def spawn(
    station: Station,
    root_context: Context,
    pool: PartPool,
    xyz: Optional[Sequence[float]] = None,
    yaw: Optional[float] = None,
) -> str:
    """Spawns the next parked part at the spawner's pose (``xyz`` / ``yaw`` instead
    if given); returns its name. Without a spawner, ``xyz`` is needed."""
    spawner = station.scenario.spawner
    if spawner is None and xyz is None:
        raise ConfigError("this scenario has no spawner: give the spawn position xyz")
    if spawner is None:
        spawner = SpawnerConfig()
    seed, index = station.scenario.seed, pool.spawn_count
    if spawner.objects and xyz is None and yaw is None:
        X_WR = reference_pose(station, root_context, spawner.reference_frame)
        X_WP = spawn_pose(spawner, seed, index, X_WR=X_WR)
        return pool.spawn(root_context, X_WP, kind_of(spawner, seed, index))
    X_WP = spawn_pose(spawner, seed, index, list(xyz) if xyz is not None else None, yaw)
    return pool.spawn(root_context, X_WP)


def reference_pose(station: Station, root_context: Context, frame: str) -> RigidTransform:
    """``X_WR`` of a spawn's reference frame as Gazebo's SpawnModel finds it: the world
    for "", ``world`` or ``map``; a Gazebo model (its origin) or a ``model::link``, by the
    course world's names (:func:`omtp_drake.cell.gazebo_models.gazebo_models`);
    SimulationError with Gazebo's message for any other name."""
    if frame in WORLD_FRAMES:
        return RigidTransform()
    plant = station.plant
    context = plant.GetMyContextFromRoot(root_context)
    name, _, link = frame.partition("::")
    for model in gazebo_models(plant, station.scenario):
        if model.name != name:
            continue
        bodies = [plant.get_body(b) for i in model.instances for b in plant.GetBodyIndices(i)]
        if not link:
            if model.X_WM is not None:
                return model.X_WM
            if bodies:
                return plant.EvalBodyPoseInWorld(context, bodies[0])
        for body in bodies:
            if body.name() == link:
                return plant.EvalBodyPoseInWorld(context, body)
    raise SimulationError(
        f"SpawnModel: reference frame {frame!r} not found, did you forget to scope the link by model name?"
    )


def world_edits(station: Station, pool: PartPool) -> list[WorldEdit]:
    """The edits the station needs: sleep, the grippers' events (weld sync), belt wrap,
    deletion wall, spawner, the models' joint pose trajectory plugins.

    Sleep comes first: a part a cup touches wakes before its weld is made."""
    edits: list[WorldEdit] = []
    if station.rest_clock is not None:
        edits.append(PartSleep(station))
    if station.grippers:
        edits.append(GripperEvents(station))
    if station.conveyor is not None:
        edits.append(BeltWrap(station))
    if station.scenario.deletion_wall and station.parts:
        edits.append(DeletionWall(station, pool))
    if station.scenario.spawner is not None:
        edits.append(AutoSpawner(station, pool))
    edits += joint_pose_trajectories(station)
    return edits


@dataclass
class _Callback:
    function: Callable[[], None]
    period: float


class Driver:
    """Owns the Simulator of a diagram holding the station and applies the
    world edits between advances.

    ``advance_to(t)`` stops only at the times an edit or a callback is due (their
    periods' multiples, and an :class:`EventSource`'s next event), applies what is
    due, and goes on: between stops the diagram runs in Drake's C++. At construction the
    simulator is initialised and every edit applied once (t = 0 edits).
    """

    def __init__(self, diagram: Diagram, context: Context, edits: Sequence[WorldEdit]):
        for edit in edits:
            if not edit.period > 0:  # (inf: an edit with nothing to do now)
                raise ConfigError(f"world edit {type(edit).__name__} needs a period > 0, got {edit.period}")
        self.diagram = diagram
        self.context = context
        self.edits = list(edits)
        self._sources = [e for e in self.edits if isinstance(e, EventSource)]
        self._callbacks: list[_Callback] = []
        tune_heap()  # (sim/heap.py: the step's memory reused, not faulted in again)
        self.simulator = Simulator(diagram, context)
        self.simulator.Initialize()
        for edit in self.edits:
            edit(context)

    @property
    def time(self) -> float:
        return self.context.get_time()

    def every(self, period: float, callback: Callable[[], None]) -> None:
        """Calls ``callback()`` at every multiple of ``period`` (after the edits due then)."""
        self._callbacks.append(_Callback(callback, check_duration("callback period", period)))

    def advance_to(self, t: float) -> None:
        """Simulates until time ``t``, stopping only where an edit, an event or a
        callback is due and applying what is due there."""
        if not math.isfinite(t):
            raise ConfigError(f"cannot advance to {t}: give a finite time")
        if t < self.time - _EPS:
            raise SimulationError(f"cannot go back in time: now {self.time:.3f} s, asked {t:.3f} s")
        # (Run at every stop: the loop's own work stays a small part of the step's.)
        context, sources, advance = self.context, self._sources, self.simulator.AdvanceTo
        get_time = context.get_time
        end = t - _EPS
        while get_time() < end:
            for source in sources:
                source.before_advance(context)
            events = [source.next_time(context) for source in sources]
            advance(self._next_stop(t, events))
            self._apply_due(events)

    def _next_stop(self, t: float, events: list[float]) -> float:
        """The first of ``t``, the sources' ``events`` and the edits' and callbacks'
        next multiples of their periods (the first ``k period`` after now, rounding errors
        below a multiple counted as on it; none for an infinite period)."""
        now = self.context.get_time()
        stop = min([t, *events])
        for periodic in (self.edits, self._callbacks):
            for item in periodic:
                period = item.period
                if period != math.inf:
                    multiple = (math.floor(now / period + _EPS) + 1) * period
                    if multiple < stop:
                        stop = multiple
        return stop

    def _apply_due(self, events: list[float]) -> None:
        """Applies the edits due now (their event, or a multiple of their period), then
        the callbacks due now (now within a rounding error of a multiple of their period;
        never for an infinite period)."""
        context = self.context
        now = context.get_time()
        due = [s for s, e in zip(self._sources, events) if abs(now - e) < _EPS]
        tolerance = _EPS * max(1.0, abs(now))
        for edit in self.edits:
            period = edit.period
            if (period != math.inf and abs(round(now / period) * period - now) < tolerance) or (
                due and any(edit is s for s in due)
            ):
                edit(context)
        for callback in self._callbacks:
            period = callback.period
            if period != math.inf and abs(round(now / period) * period - now) < tolerance:
                callback.function()
