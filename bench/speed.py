"""How fast the cell runs: the measurements of ``bench_speed.py`` and ``omtp-drake bench``.

Each case runs the scenario as users run it (*full*: every system of ours on) and
its *bare* plant: the same MultibodyPlant and SceneGraph (bodies, geometries,
contact model, time step, parked pool, from :func:`station.add_cell_models`), each
arm held at its initial pose by the same servo (command sampler and inverse
dynamics fed by a constant, all C++), the belt at its speed, and none of our
Python systems (cameras, grippers, beam, controller, driver). Their difference is
our overhead over the physical limit of a cell whose arms stand still.

Cases (wall milliseconds per simulated second, the median of ``repeats``):

- ``fill_bin``: full = ``run_task("fill_bin")`` (10 parts); bare = holding still
  with one part on the floor.
- ``lecture7_conveyor_pick``: full = its task (2 parts); bare = one part on the belt.
- ``lecture7_conveyor`` with 10 parts riding the belt (beam stop off): full =
  :class:`FactoryRuntime`; bare = the same parts on the same belt.
- ``fill_bin`` at a 2 ms step (``SMALL_STEP``), for users who ask for a finer step.

Targets: ``fill_bin`` and ``lecture7_conveyor_pick`` <= 60 ms per simulated
second, the belt <= 50 (RTF >= 20), ``fill_bin`` at 2 ms <= 120.

The fair reference: ``fill_bin``'s full run, at its step and at 2 ms,
against its bare plant *replaying the same arm motion*: each arm's position commands,
as its servo sampled them (``command_rate_hz``) in a recorded run of the task, fed
through the same C++ sampler and servo, with the same one part on the floor and the same parked pool; no
suction, so no part is carried. An arm whose command was held in the run is locked,
as the station locks it. Both in CPU seconds of this process per simulated
second (the machine is shared; CPU time is less noisy than wall time), the median of
``repeats``, interleaved. At 2 ms the replay is also the floor under the 120 ms target:
whatever it leaves is all the full run may add (DiffIK, our systems, the carried parts).

Also the diagram build time, the pick cycle times of ``fill_bin``, and (with py-spy
installed) a row per part of ``fill_bin``'s native profile (bench/profile_split.py),
so that the table says where the time goes.
"""

from __future__ import annotations

import importlib.util
import logging
import math
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Optional

import numpy as np
from pydrake.multibody.plant import AddMultibodyPlant
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, DiagramBuilder, EventStatus
from pydrake.systems.primitives import ConstantVectorSource, TrajectorySource
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.bench_command import bench_module
from omtp_drake.cell import arms
from omtp_drake.cell.conveyor import BeltGeometry, belt_desired_state
from omtp_drake.cell.parts import PartStates
from omtp_drake.cell.station import add_cell_models, build_station
from omtp_drake.errors import BenchmarkError, ConfigError
from omtp_drake.scenario import PartConfig, Scenario, load_scenario
from omtp_drake.sim.heap import tune_heap
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.tasks.run import TaskResult, TaskRun, prepare, run_task

log = logging.getLogger(__name__)

#: The finer step a user may ask for, measured as its own case (target: <= 120 ms/s).
SMALL_STEP = 0.002
#: The full run over the bare plant replaying its arm motion (issue 38: <= 1.5x).
REPLAY_RATIO_TARGET = 1.5
#: Shares of fill_bin's run the profile's parts should stay under (issue 38).
PROFILE_TARGETS = {"our Python": 0.05, "simulator overhead": 0.08}

_BELT = BeltGeometry.from_model()


def _on_belt(y: float, size: float = 0.2) -> list[float]:
    """Where a part of edge ``size`` rests on the belt's centre line at ``y``."""
    return [_BELT.x, y, _BELT.top + size / 2 + 0.001]


def bare_simulator(
    scenario: Scenario, motion: Optional[ArmMotion] = None, holds: Optional[dict] = None
) -> tuple[Simulator, object]:
    """The bare plant of ``scenario`` (see the module doc), initialized: each arm held
    at its initial pose, or replaying its commands from ``motion``. Also returns what
    the simulator needs kept alive (the servos' arm models). ``holds``: filled with the
    weld grippers' constraints (declared, off), for a replay that carries the parts
    (bench/replay_parts.py)."""
    tune_heap()  # as the driver does: the same heap for the full run and the bare plant
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(scenario.plant_config, builder)
    plant.mutable_gravity_field().set_gravity_vector(scenario.gravity)
    models = add_cell_models(plant, scene_graph, scenario)
    if holds is not None:
        holds.update(_sibling("replay_parts").declare_holds(plant, models))
    plant.Finalize()
    samplers = {}
    for name, handles in models.arms.items():
        q = arms.named_pose(handles.config.initial_pose, handles.config)
        sampler, _, handles.control_plant = arms.add_arm_controller(
            builder, plant, handles.arm, handles.config, scenario.gravity
        )
        if motion is not None and name in motion.commands:
            q = motion.commands[name].value(0.0)[:, 0]
            source = builder.AddSystem(TrajectorySource(motion.commands[name]))
        else:
            source = builder.AddSystem(ConstantVectorSource(q))
        sampler.connect_from(builder, source.get_output_port())
        samplers[name] = (sampler, q)
    if models.conveyor is not None:
        power = scenario.conveyor.power if scenario.conveyor else 0.0
        belt = builder.AddSystem(ConstantVectorSource(belt_desired_state(power)))
        builder.Connect(belt.get_output_port(), plant.get_desired_state_input_port(models.conveyor))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    for name, (sampler, q) in samplers.items():
        plant.SetPositions(plant_context, models.arms[name].arm, q)
        sampler.set_initial_position(context, q)
    part_states = PartStates(plant, scene_graph, models.parts)
    for name in models.pool:  # parked as the station parks them
        part_states.park(context, name)
    for constraints in (holds or {}).values():
        constraints.deactivate_all(plant, plant_context)
    if motion is not None:  # as the station locks an arm whose command is held
        for name in set(models.arms) - set(motion.moving):
            arms.lock_arm(plant, plant_context, models.arms[name].arm, True)
    simulator = Simulator(diagram, context)
    simulator.Initialize()
    return simulator, models


def bare_plant_seconds(scenario: Scenario, seconds: float) -> float:
    """Wall seconds per simulated second of ``scenario``'s bare plant, arms held still
    (see the module doc)."""
    simulator, _models = bare_simulator(scenario)
    start = time.perf_counter()
    simulator.AdvanceTo(seconds)
    return (time.perf_counter() - start) / seconds


@dataclass(frozen=True)
class ArmMotion:
    """The position commands each arm's servo sampled in a run (``commands[robot]``: a
    zero-order hold of the samples, switching half a period before each sample time
    so that the servo's sampler reads the same values), and how long the run was."""

    commands: dict[str, PiecewisePolynomial]
    duration: float
    #: The arms whose command changed in the run (a task's controller drives them);
    #: the others' commands were held, and the station locked them.
    moving: frozenset[str] = frozenset()
    #: The run's edits of its parts (bench/replay_parts.py), for a replay that carries them.
    parts: tuple = ()


def record_arm_motion(name: Scenario | str) -> tuple[ArmMotion, TaskResult]:
    """Runs ``name``'s task (a scenario or its name) and records each arm's position
    command as its servo samples it (at ``command_rate_hz``, the value at each sample
    instant)."""
    samples: dict[str, dict[int, np.ndarray]] = {}
    periods: dict[str, float] = {}
    edits: list = []

    def start(run: TaskRun) -> None:
        station = run.runtime.station
        station_context = station.diagram.GetMyContextFromRoot(run.runtime.context)
        ports = {}
        for robot in station.scenario.robots:
            periods[robot.name] = 1.0 / robot.command_rate_hz
            ports[robot.name] = station.diagram.GetInputPort(f"{robot.name}.position")
            samples[robot.name] = {}
        run_edits, after_step = _sibling("replay_parts").watch_parts(run)
        edits.append(run_edits)

        def monitor(context: Context) -> EventStatus:
            # Called after each step, before the updates at its end time: the
            # command the sampler reads at t = k h is the port's value now.
            t = context.get_time()
            for robot, port in ports.items():
                k = round(t / periods[robot])
                if abs(t - k * periods[robot]) < 1e-9 and k not in samples[robot]:
                    samples[robot][k] = np.array(port.Eval(station_context))
            after_step(context)
            return EventStatus.Succeeded()

        monitor(run.runtime.context)  # the sample at t = 0
        run.runtime.simulator.set_monitor(monitor)

    result = run_task(name, on_start=start)
    commands = {}
    for robot, by_k in samples.items():
        ks = sorted(by_k)
        h = periods[robot]
        breaks = [(k - 0.5) * h for k in ks] + [(ks[-1] + 0.5) * h]
        values = np.column_stack([by_k[k] for k in ks] + [by_k[ks[-1]]])
        commands[robot] = PiecewisePolynomial.ZeroOrderHold(breaks, values)
    moving = frozenset(
        robot for robot, by_k in samples.items() if np.ptp(np.stack(list(by_k.values())), axis=0).max() > 0
    )
    return ArmMotion(commands, result.sim_time_s, moving, tuple(edits[0])), result


def replay_cpu_seconds(scenario: Scenario, motion: ArmMotion) -> float:
    """CPU seconds (this process) per simulated second of ``scenario``'s bare plant
    replaying ``motion`` (the same servo, none of our Python systems)."""
    return replay_seconds(scenario, motion)[0]


def replay_seconds(scenario: Scenario, motion: ArmMotion, parts: bool = False) -> tuple[float, float]:
    """CPU (this process) and wall seconds per simulated second of ``scenario``'s bare
    plant replaying ``motion``; with ``parts``, also carrying the run's parts as it did
    (``scenario``: the run's own, with its pool; bench/replay_parts.py)."""
    holds: Optional[dict] = {} if parts else None
    simulator, models = bare_simulator(scenario, motion, holds)
    cpu, wall = time.process_time(), time.perf_counter()
    if parts:
        _sibling("replay_parts").advance_with_parts(simulator, models, holds, motion.parts, motion.duration)
    else:
        simulator.AdvanceTo(motion.duration)
    return (time.process_time() - cpu) / motion.duration, (time.perf_counter() - wall) / motion.duration


def with_parts(scenario: Scenario, xyzs: Sequence[Sequence[float]], size: float) -> Scenario:
    """``scenario`` with only these parts (0.2 kg cubes of edge ``size``), no spawner, no task."""
    parts = [PartConfig(name=f"bench_{k}", xyz=list(p), size=size, mass=0.2) for k, p in enumerate(xyzs)]
    return replace(scenario, parts=parts, spawner=None, task=None)


def belt_scenario(parts: int) -> Scenario:
    """``lecture7_conveyor`` with ``parts`` parts 0.45 m apart riding the belt at full
    power, the beam's stop off (so they keep riding)."""
    s = load_scenario("lecture7_conveyor")
    if s.conveyor is None:
        raise ConfigError("lecture7_conveyor has no conveyor")
    s = replace(s, conveyor=replace(s.conveyor, stop_on_beam=False, power=100.0), part_pool=0)
    return with_parts(s, [_on_belt(4.6 - 0.45 * k) for k in range(parts)], 0.2)


def task_seconds(name: str, time_step: Optional[float] = None) -> tuple[float, TaskResult]:
    """Wall seconds per simulated second of the scenario's task (full), and its result;
    ``time_step``: the plant's step instead of the scenario's."""
    scenario = prepare(name)
    if time_step is not None:
        scenario = scenario.with_time_step(time_step)
    result = run_task(scenario)
    if not result.success:
        raise BenchmarkError(f"{name} did not succeed in the benchmark: {result.summary}")
    return result.wall_time_s / result.sim_time_s, result


def belt_seconds(parts: int, seconds: float) -> float:
    """Wall seconds per simulated second of :func:`belt_scenario` with every system on."""
    rt = FactoryRuntime(belt_scenario(parts))
    start = time.perf_counter()
    rt.advance_to(seconds)
    return (time.perf_counter() - start) / seconds


@dataclass(frozen=True)
class CaseTiming:
    """One case: wall seconds per simulated second, bare and full, and the target for
    the full run."""

    case: str
    bare: float
    full: float
    target: float

    @property
    def overhead(self) -> float:
        """Our systems' share over the bare plant (0.25 = 25 %)."""
        return (self.full - self.bare) / self.bare


@dataclass(frozen=True)
class ReplayTiming:
    """One case against the bare plant replaying the same arm motion: CPU seconds of
    this process per simulated second, full run and replay (and the same in wall
    seconds)."""

    case: str
    replay: float
    full: float
    replay_wall: float = math.nan
    full_wall: float = math.nan
    #: The replay carrying the run's parts as it did (bench/replay_parts.py); nan: not measured.
    replay_parts: float = math.nan

    @property
    def ratio(self) -> float:
        """The full run's cost over the replay's (target: <= 1.5, issue 38)."""
        return self.full / self.replay

    @property
    def parts_ratio(self) -> float:
        """The full run's cost over the replay that carries its parts."""
        return self.full / self.replay_parts

    @property
    def wall_ratio(self) -> float:
        return self.full_wall / self.replay_wall


@dataclass(frozen=True)
class SpeedRow:
    """One row of the speed table: what was measured, the value and the target as
    shown, and whether the target is met."""

    what: str
    measured: str
    target: str
    met: bool


@dataclass(frozen=True)
class SpeedReport:
    """What :func:`measure` measured."""

    cases: tuple[CaseTiming, ...]
    station_build_s: float
    task_build_s: float
    cycles: tuple[float, ...]
    repeats: int
    replays: tuple[ReplayTiming, ...] = ()
    #: fill_bin's native profile split (bench/profile_split.py): (part, share of the
    #: run's samples); empty when py-spy could not record (see ``profile_note``).
    profile: tuple[tuple[str, float], ...] = ()
    profile_note: str = ""
    #: fill_bin's job in the peer engines (bench/bench_peers.py): (engine, CPU seconds per
    #: simulated second, target for ours over it); empty when not measured (``peer_note``).
    peers: tuple[tuple[str, float, float], ...] = ()
    peer_note: str = ""

    def rows(self) -> list[SpeedRow]:
        """The speed table's rows: what, measured, target, met."""
        rows = [
            SpeedRow(
                f"{c.case}: wall ms per simulated s (RTF)",
                f"{1e3 * c.full:.0f} ({1 / c.full:.1f})",
                f"<= {1e3 * c.target:.0f} (>= {1 / c.target:.1f})",
                c.full <= c.target,
            )
            for c in self.cases
        ]
        rows += [
            SpeedRow(
                f"{c.case}: bare plant ms/s, our overhead",
                f"{1e3 * c.bare:.0f}, {100 * c.overhead:.0f} %",
                "<= 25 %",
                c.overhead <= 0.25,
            )
            for c in self.cases
        ]
        rows += [
            SpeedRow(
                f"{r.case}: CPU ms/s, full / same motion replayed",
                f"{1e3 * r.full:.0f} / {1e3 * r.replay:.0f} = {r.ratio:.2f}x",
                f"<= {REPLAY_RATIO_TARGET}x",
                r.ratio <= REPLAY_RATIO_TARGET,
            )
            for r in self.replays
        ]
        rows += [
            SpeedRow(
                f"{r.case}: CPU ms/s, full / same motion and parts replayed",
                f"{1e3 * r.full:.0f} / {1e3 * r.replay_parts:.0f} = {r.parts_ratio:.2f}x",
                "(reference)",
                True,
            )
            for r in self.replays
            if math.isfinite(r.replay_parts)
        ]
        rows += [
            SpeedRow(
                f"{r.case}: wall ms/s, full / same motion replayed",
                f"{1e3 * r.full_wall:.0f} / {1e3 * r.replay_wall:.0f} = {r.wall_ratio:.2f}x",
                f"<= {REPLAY_RATIO_TARGET}x",
                r.wall_ratio <= REPLAY_RATIO_TARGET,
            )
            for r in self.replays
            if math.isfinite(r.full_wall)
        ]
        ours = self.replays[0].full if self.replays else math.nan
        rows += [
            SpeedRow(
                f"fill_bin against {engine} at its defaults: CPU ms/s, ours / its",
                f"{1e3 * ours:.0f} / {1e3 * cpu:.0f} = {ours / cpu:.2f}x",
                f"<= {target}x",
                ours / cpu <= target,
            )
            for engine, cpu, target in self.peers
        ]
        rows += [
            SpeedRow(
                f"fill_bin profile (py-spy, of the run): {part}",
                f"{100 * share:.1f} %",
                f"<= {100 * PROFILE_TARGETS[part]:.0f} %" if part in PROFILE_TARGETS else "",
                share <= PROFILE_TARGETS.get(part, 1.0),
            )
            for part, share in self.profile
        ]
        rows.append(
            SpeedRow(
                "diagram build, fill_bin station / with task (s)",
                f"{self.station_build_s:.2f} / {self.task_build_s:.2f}",
                "<= 0.5",
                self.task_build_s <= 0.5,
            )
        )
        mean, worst = statistics.mean(self.cycles), max(self.cycles)
        rows.append(
            SpeedRow(
                f"pick cycle, fill_bin, {len(self.cycles)} picks: mean / worst (s)",
                f"{mean:.2f} / {worst:.2f}",
                "<= 6.0 / 7.0",
                mean <= 6.0 and worst <= 7.0,
            )
        )
        return rows

    def table(self) -> str:
        """:meth:`rows` as a text table, and how they were measured."""
        rows = self.rows()
        width = max(len(r.what) for r in rows)
        lines = [f"{'what':<{width}}  {'measured':>16}  {'target':>14}  met", "-" * (width + 40)]
        lines += [
            f"{r.what:<{width}}  {r.measured:>16}  {r.target:>14}  {'yes' if r.met else 'NO'}" for r in rows
        ]
        lines.append(
            f"(medians of {self.repeats} interleaved rounds: each round runs every case once."
            "\n Wall-time rows: bare plant = each arm held still;"
            "\n CPU rows (this process): bare plant = the same run's arm commands replayed by the same servo)"
        )
        lines += [note for note in (self.profile_note, self.peer_note) if note]
        return "\n".join(lines)


def _build_seconds(build: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        build()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def measure(
    repeats: int = 2, bare_seconds: float = 10.0, progress: Optional[Callable[[str], None]] = None
) -> SpeedReport:
    """Runs every case ``repeats`` times, in rounds that run each case (bare plant, then
    full run) once, so a busy minute on a shared machine touches every case alike; reports
    the medians (the targets are medians of interleaved runs). A few minutes at 2."""
    if repeats < 1:
        raise ConfigError(f"repeats must be >= 1, got {repeats}")
    if not bare_seconds > 0:
        raise ConfigError(f"bare_seconds must be > 0, got {bare_seconds}")
    say = progress or (lambda text: log.info(text))
    # The bare plants park the same pool as the full runs.
    fill, pick = prepare("fill_bin"), prepare("lecture7_conveyor_pick")
    say("diagram build")
    build_station(load_scenario("fill_bin"))  # warm the model cache and imports
    station_build = _build_seconds(lambda: build_station(load_scenario("fill_bin")), max(3, repeats))
    task_build = _build_seconds(lambda: TaskRun(prepare("fill_bin")), max(3, repeats))
    results: list[TaskResult] = []

    def full_task(name: str, time_step: Optional[float] = None) -> float:
        seconds, result = task_seconds(name, time_step)
        if time_step is None:
            results.append(result)
        return seconds

    fill_floor = with_parts(fill, [[-8.3, -1.23, 0.051]], fill.pool_part_size)
    fine = SMALL_STEP
    fine_label = f"fill_bin (10 parts) at a {1e3 * fine:g} ms step"
    plan = (  # (label, bare scenario, full run, target: wall s per simulated s)
        ("fill_bin (10 parts)", fill_floor, lambda: full_task("fill_bin"), 0.060),
        (
            "lecture7_conveyor_pick (2 parts)",
            with_parts(pick, [_on_belt(1.8)], 0.2),
            lambda: full_task("lecture7_conveyor_pick"),
            0.060,
        ),
        (
            "lecture7_conveyor, 10 parts on the belt",
            belt_scenario(10),
            lambda: belt_seconds(10, bare_seconds),
            0.050,
        ),
        (
            fine_label,
            fill_floor.with_time_step(fine),
            lambda: full_task("fill_bin", fine),
            0.120,
        ),
    )
    bares: list[list[float]] = [[] for _ in plan]
    fulls: list[list[float]] = [[] for _ in plan]
    for round_ in range(repeats):
        for k, (label, bare_scenario, full, _target) in enumerate(plan):
            say(f"{label} (round {round_ + 1} of {repeats})")
            bares[k].append(bare_plant_seconds(bare_scenario, bare_seconds))
            fulls[k].append(full())
    cases = [
        CaseTiming(label, statistics.median(bares[k]), statistics.median(fulls[k]), target)
        for k, (label, _bare, _full, target) in enumerate(plan)
    ]
    say("fill_bin, at its step and at 2 ms, against the same arm motion replayed")
    replays = (
        replay_timing("fill_bin", fill, fill_floor, repeats, with_parts=fill),
        replay_timing(fine_label, fill.with_time_step(fine), fill_floor.with_time_step(fine), repeats),
    )
    fill_runs = [r for r in results if r.scenario == "fill_bin"]
    cycles = tuple(p.cycle_time for p in fill_runs[0].picks if p.success)
    say("fill_bin's native profile (py-spy)")
    profile, note = _profile_split_module().profile_parts("fill_bin")
    say("fill_bin's job in PyBullet and MuJoCo (bench/bench_peers.py)")
    try:
        peers, peer_note = bench_module("bench_peers").peer_timings(repeats), ""
    except ImportError as e:  # the bench extra's engines
        peers, peer_note = (), f"no peer rows: {e.name} is not installed (pip install -e '.[bench]')"
    return SpeedReport(
        tuple(cases), station_build, task_build, cycles, repeats, replays, profile, note, peers, peer_note
    )


def replay_timing(
    label: str, scenario: Scenario, bare: Scenario, repeats: int, with_parts: Optional[Scenario] = None
) -> ReplayTiming:
    """``scenario``'s task (CPU per simulated second, the median of ``repeats``) against
    ``bare`` replaying the arm commands recorded in one more run of it; interleaved. With
    ``with_parts`` (the run's scenario, its pool), also against that bare plant replaying
    the same commands and carrying the run's parts as it did (bench/replay_parts.py)."""
    motion, _ = record_arm_motion(scenario)
    full, replay, full_wall, replay_wall, carried = [], [], [], [], []
    for _ in range(repeats):
        cpu, wall = time.process_time(), time.perf_counter()
        result = run_task(scenario)
        full.append((time.process_time() - cpu) / result.sim_time_s)
        full_wall.append((time.perf_counter() - wall) / result.sim_time_s)
        replayed = replay_seconds(bare, motion)
        replay.append(replayed[0])
        replay_wall.append(replayed[1])
        if with_parts is not None:
            carried.append(replay_seconds(with_parts, motion, parts=True)[0])
    return ReplayTiming(
        label,
        statistics.median(replay),
        statistics.median(full),
        statistics.median(replay_wall),
        statistics.median(full_wall),
        statistics.median(carried) if carried else math.nan,
    )


def _profile_split_module():
    """bench/profile_split.py (beside this file), imported by path."""
    return _sibling("profile_split")


def _sibling(stem: str):
    """bench/<stem>.py (beside this file), imported by path once."""
    name = f"omtp_bench_{stem}"
    if name in sys.modules:
        return sys.modules[name]
    path = Path(__file__).resolve().parent / f"{stem}.py"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise BenchmarkError(f"cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # (its dataclasses look their module up by name)
    spec.loader.exec_module(module)
    return module
