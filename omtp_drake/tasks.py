"""Tasks: run a scenario's pick-and-place task and judge it.

A task (``Scenario.task``) says which robot puts how many parts into which
bin; the scenario's spawner says where parts appear; the planner
(:mod:`omtp_drake.pick_and_place`) and the gripper do the work. Success: all
``parts`` parts in the bin, none disposed of, none left loose, none held.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Optional

from omtp_drake.errors import ConfigError
from omtp_drake.parts import Ledger
from omtp_drake.pick_and_place import ControllerStatus, PickRecord, add_pick_and_place
from omtp_drake.runtime import FactoryRuntime
from omtp_drake.scenario import Scenario, load_scenario
from omtp_drake.visualization import (add_visual_extras, save_recording, start_meshcat,
                                      start_recording, view_for)

_log = logging.getLogger(__name__)


@dataclass
class TaskResult:
    """The outcome of one run (``to_dict`` is the CLI's JSON)."""

    scenario: str
    seed: int
    picks: list[PickRecord]
    ledger: Ledger
    success: bool
    sim_time_s: float
    wall_time_s: float
    bin: str
    parts: int
    statuses: list[ControllerStatus] = field(default_factory=list, repr=False)

    @property
    def summary(self) -> dict:
        attempted = [p for p in self.picks if p.part]
        succeeded = [p for p in attempted if p.success]
        cycles = [p.cycle_time for p in succeeded]
        return {
            "attempted": len(attempted),
            "succeeded": len(succeeded),
            "failed": len(attempted) - len(succeeded),
            "mean_cycle_time_s": sum(cycles) / len(cycles) if cycles else math.nan,
            "max_cycle_time_s": max(cycles) if cycles else math.nan,
            "sim_time_s": self.sim_time_s,
            "wall_time_s": self.wall_time_s,
            "real_time_factor": self.sim_time_s / self.wall_time_s if self.wall_time_s else math.inf,
            "in_bin": self.ledger.in_bin.get(self.bin, 0),
            "parts": self.parts,
            "success": self.success,
        }

    def to_dict(self) -> dict:
        return {"scenario": self.scenario, "seed": self.seed,
                "picks": [p.to_dict() for p in self.picks],
                "summary": self.summary, "ledger": self.ledger.to_dict()}


def prepare(scenario: Scenario | str, *, seed: Optional[int] = None,
            parts: Optional[int] = None) -> Scenario:
    """The scenario with the run's overrides (seed, number of parts) applied."""
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    if scenario.task is None:
        raise ConfigError(f"scenario {scenario.name!r} has no task to run")
    if seed is not None:
        scenario = replace(scenario, seed=int(seed))
    if parts is not None:
        if parts < 1:
            raise ConfigError(f"--parts must be >= 1, got {parts}")
        scenario = replace(scenario, task=replace(scenario.task, parts=int(parts)))
    n = scenario.task.parts
    if scenario.spawner is not None:
        scenario = replace(scenario, spawner=replace(scenario.spawner, max_parts=n),
                           part_pool=max(scenario.part_pool, n + 2))
    scenario.validate()
    return scenario


class TaskRun:
    """A runtime with the task's controller, ready to advance (used by tests and notebooks)."""

    def __init__(self, scenario: Scenario, *, meshcat=None):
        self.scenario = scenario
        task = scenario.task
        self._controller = None

        def extend(builder, station):
            self._controller, self._diffik = add_pick_and_place(builder, station, task)

        self.runtime = FactoryRuntime(scenario, meshcat=meshcat, extend=extend)
        rt = self.runtime
        q0 = rt.station.plant.GetPositions(rt._plant_context, rt.station.arm(task.robot).arm)
        self._diffik.SetPositions(self._diffik.GetMyMutableContextFromRoot(rt.context), q0)
        if rt.station.conveyor is not None and rt.station.break_beam is not None:
            rt.on_tick(_restart_belt_when_beam_clears)

    def status(self) -> ControllerStatus:
        return self._controller.GetOutputPort("status").Eval(
            self._controller.GetMyContextFromRoot(self.runtime.context))

    def done(self) -> bool:
        ledger = self.runtime.ledger()
        status = self.status()
        return (ledger.in_bin.get(self.scenario.task.bin, 0) >= self.scenario.task.parts
                and status.mode in ("HOME", "WAIT_PART"))


def _restart_belt_when_beam_clears(rt: FactoryRuntime) -> None:
    """The conveyor task: once the robot has taken the part off the beam, run the belt again."""
    if rt.conveyor_power() == 0.0 and not rt.break_beam()[0]:
        rt.set_conveyor_power(100.0)


def run_task(
    scenario: Scenario | str,
    *,
    seed: Optional[int] = None,
    duration: Optional[float] = None,
    parts: Optional[int] = None,
    meshcat: bool = False,
    record: Optional[str | Path] = None,
    progress: bool = False,
    chunk: float = 0.5,
    on_chunk: Optional[Callable[[TaskRun], None]] = None,
    on_start: Optional[Callable[[TaskRun], None]] = None,
) -> TaskResult:
    """Runs the scenario's task until it succeeds or ``duration`` (default: 30 s per part).

    ``on_start(run)`` is called once before the first advance (e.g. to attach a
    :class:`omtp_drake.plots.RunRecorder`); ``on_chunk(run)`` after every chunk.
    """
    scenario = prepare(scenario, seed=seed, parts=parts)
    n = scenario.task.parts
    limit = duration if duration is not None else 30.0 * n
    if limit <= 0:
        raise ConfigError(f"--duration must be > 0, got {limit}")
    viewer = start_meshcat(view_for(scenario)) if (meshcat or record) else None
    run = TaskRun(scenario, meshcat=viewer)
    rt = run.runtime
    if record:
        start_recording(rt.station.visualizer)
    if viewer is not None:
        add_visual_extras(rt, recording=bool(record))  # camera frusta, detection markers
    if on_start is not None:
        on_start(run)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n, desc=scenario.name, unit="part")
    wall0 = time.perf_counter()
    placed = 0
    while rt.time < limit - 1e-9:
        rt.advance_to(min(limit, rt.time + chunk))
        if on_chunk is not None:
            on_chunk(run)
        if bar is not None:
            now = rt.ledger().in_bin.get(scenario.task.bin, 0)
            bar.update(now - placed)
            placed = now
        if run.done():
            break
    wall = time.perf_counter() - wall0
    if bar is not None:
        bar.close()
    if record:
        save_recording(rt.station.visualizer, viewer, record)
    ledger = rt.ledger()
    status = run.status()
    in_bin = ledger.in_bin.get(scenario.task.bin, 0)
    success = (in_bin == n and ledger.disposed == 0 and ledger.on_floor == 0
               and ledger.on_belt == 0 and sum(ledger.held.values()) == 0)
    return TaskResult(scenario=scenario.name, seed=scenario.seed, picks=list(status.picks),
                      ledger=ledger, success=success, sim_time_s=rt.time, wall_time_s=wall,
                      bin=scenario.task.bin, parts=n)
