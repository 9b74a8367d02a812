"""Tasks: run a scenario's pick-and-place task and judge it.

A task (``Scenario.task``) says which robot puts how many parts into which
bin; the scenario's spawner says where parts appear; the planner
(:mod:`omtp_drake.control.pick_and_place`) and the gripper do the work.

Success is judged from what happened, not from what was hoped, in two parts
reported apart: the goal (``parts`` parts in the bin and nothing lost: no part
disposed of, left loose or still held) and the picks (each part in the bin put
there by a successful place, not dropped into it). A run succeeds when both hold.
"""

from __future__ import annotations

import collections
import logging
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Optional

from omtp_drake.control.pick_and_place import (
    ControlState,
    Mode,
    PickAndPlaceController,
    PickHistory,
    PickRecord,
    add_pick_and_place,
    bin_capacity,
    control_of,
    history_of,
)
from omtp_drake.errors import ConfigError, check_duration
from omtp_drake.scenario import Scenario, as_scenario
from omtp_drake.sim.faults import fault_line
from omtp_drake.sim.ledger import Ledger
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.viz.meshcat import add_visual_extras, save_recording, start_meshcat, start_recording, view_for

_log = logging.getLogger(__name__)

#: The task's bookkeeping (a given-up part written off, the belt restarted once the beam
#: clears) runs every 0.1 s, at the sleep check's stops: at the runtime's 50 ms ticks it
#: made the driver stop 20 times a simulated second for it alone, and 50 ms later changes
#: no outcome (bench/README.md, "Round five").
TASK_TICK = 0.1


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
    #: The scenario's faults that struck (FaultReport.to_dict: what, when, the effect).
    faults: list[dict[str, Any]] = field(default_factory=list)

    @property
    def summary(self) -> dict:
        """Counts that equal what the records and the ledger say."""
        succeeded = [p for p in self.picks if p.success]
        failed = [p for p in self.picks if not p.success]
        cycles = [p.cycle_time for p in succeeded]
        return {
            "attempted": len(self.picks),
            "succeeded": len(succeeded),
            "failed": len(failed),
            "failure_reasons": dict(collections.Counter(p.reason.value for p in failed if p.reason)),
            "mean_cycle_time_s": sum(cycles) / len(cycles) if cycles else math.nan,
            "max_cycle_time_s": max(cycles) if cycles else math.nan,
            "sim_time_s": self.sim_time_s,
            "wall_time_s": self.wall_time_s,
            "real_time_factor": self.sim_time_s / self.wall_time_s if self.wall_time_s else math.inf,
            "in_bin": self.ledger.in_bin.get(self.bin, 0),
            "parts": self.parts,
            "goal_met": self.goal_met,
            "placed_by_picks": self.placed_by_picks,
            "success": self.success,
        }

    @property
    def goal_met(self) -> bool:
        """The task's goal: its parts in the bin and nothing lost (see :func:`goal_met`)."""
        return goal_met(self.ledger, self.bin, self.parts)

    @property
    def placed_by_picks(self) -> bool:
        """Each part in the bin got there by a successful place (see :func:`placed_by_picks`)."""
        return placed_by_picks(self.picks, self.ledger, self.bin)

    @property
    def verdict(self) -> str:
        """One line: SUCCESS, or FAILED saying whether the goal was met and, if it was,
        which parts in the bin no pick placed."""
        if self.success:
            return "SUCCESS"
        count = f"{self.ledger.in_bin.get(self.bin, 0)}/{self.parts} parts in {self.bin}"
        if not self.goal_met:
            lost = self.ledger.disposed + self.ledger.loose + sum(self.ledger.held.values())
            return f"FAILED: goal not met ({count}" + (f", {lost} lost or held)" if lost else ")")
        placed = {p.part for p in self.picks if p.success}
        unplaced = sorted(n for n in _in_bin(self.ledger, self.bin) if n not in placed)
        how = {p.part: p.reason for p in self.picks if p.reason is not None}
        names = ", ".join(f"{n} ({how[n]})" if n in how else n for n in unplaced)
        return f"FAILED: goal met ({count}), but not all by a pick: {names}"

    @property
    def unaccounted_parts(self) -> list[str]:
        """Parts left loose (on the belt, the floor or elsewhere, not held, not in a
        bin) that the controller did not give up on: a part given up on has a record
        (``given_up``) saying where it lies."""
        given_up = {p.part for p in self.picks if p.given_up}
        loose = [n for n, place in self.ledger.parts.items() if not place.startswith(("in_bin", "held"))]
        return sorted(n for n in loose if n not in given_up)

    @property
    def accounted_for(self) -> bool:
        """Every part that entered the world is accounted for: the ledger balances and
        no part is left loose unrecorded."""
        return self.ledger.balanced and not self.unaccounted_parts

    def format(self) -> str:
        """The result as ``omtp-drake run`` prints it: a line per pick, the counts, the
        ledger, a line per fault that struck and the verdict."""
        summary = self.summary
        lines = [f"{'part':>10} {'start s':>8} {'end s':>8} {'cycle s':>8} {'attempt':>7}  result"]
        for pick in self.picks:
            outcome = "ok" if pick.success else f"failed: {pick.reason}"
            if pick.position is not None:  # where the part lies (a drop: where it landed)
                outcome += " at ({:.2f}, {:.2f}, {:.2f})".format(*pick.position)
            lines.append(
                f"{pick.part or '-':>10} {pick.start:8.2f} {pick.end:8.2f} {pick.cycle_time:8.2f} "
                f"{pick.attempt:7d}  {outcome}"
            )
        lines.append(
            f"{self.scenario} (seed {self.seed}): {summary['in_bin']}/{summary['parts']} parts "
            f"in {self.bin}; {summary['succeeded']} picks ok, {summary['failed']} failed; "
            f"{_mean_cycle(summary['succeeded'], summary['mean_cycle_time_s'])}; "
            f"{summary['sim_time_s']:.1f} s simulated in {summary['wall_time_s']:.1f} s "
            f"(real-time factor {summary['real_time_factor']:.1f})"
        )
        lines.append(self.ledger.summary_line())
        lines += [f"fault: {fault_line(fault)}" for fault in self.faults]
        lines.append(self.verdict)
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {
            "scenario": self.scenario,
            "seed": self.seed,
            "picks": [p.to_dict() for p in self.picks],
            "summary": self.summary,
            "ledger": self.ledger.to_dict(),
            "faults": self.faults,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], bin: str) -> TaskResult:
        """The result of :meth:`to_dict`, for the task's bin ``bin``."""
        summary = data["summary"]
        return cls(
            scenario=data["scenario"],
            seed=data["seed"],
            picks=[PickRecord.from_dict(p) for p in data["picks"]],
            ledger=Ledger.from_dict(data["ledger"]),
            success=summary["success"],
            sim_time_s=summary["sim_time_s"],
            wall_time_s=summary["wall_time_s"],
            bin=bin,
            parts=summary["parts"],
            faults=list(data.get("faults", [])),
        )


def _in_bin(ledger: Ledger, bin_name: str) -> set[str]:
    return {n for n, where in ledger.parts.items() if where == f"in_bin:{bin_name}"}


def goal_met(ledger: Ledger, bin_name: str, parts: int) -> bool:
    """The task's goal: at least ``parts`` parts in the bin, and nothing lost (no part
    disposed of, left loose or still held), however they got there."""
    return (
        len(_in_bin(ledger, bin_name)) >= parts
        and ledger.disposed == 0
        and ledger.loose == 0
        and sum(ledger.held.values()) == 0
    )


def placed_by_picks(picks: list[PickRecord], ledger: Ledger, bin_name: str) -> bool:
    """Each part in the bin was put there by a successful place (none fell in)."""
    return _in_bin(ledger, bin_name) <= {p.part for p in picks if p.success}


def judge(picks: list[PickRecord], ledger: Ledger, bin_name: str, parts: int) -> bool:
    """Did the task succeed: its goal met (:func:`goal_met`) and every part in the bin
    placed by a pick (:func:`placed_by_picks`)?"""
    return goal_met(ledger, bin_name, parts) and placed_by_picks(picks, ledger, bin_name)


def prepare(scenario: Scenario | str, *, seed: Optional[int] = None, parts: Optional[int] = None) -> Scenario:
    """The scenario with the run's overrides (seed, number of parts) applied."""
    scenario = as_scenario(scenario)
    task = scenario.required_task()
    if seed is not None:
        if isinstance(seed, bool) or int(seed) != seed or seed < 0:
            raise ConfigError(f"--seed must be an integer >= 0, got {seed!r}")
        scenario = replace(scenario, seed=int(seed))
    if parts is not None:
        if parts < 1:
            raise ConfigError(f"--parts must be >= 1, got {parts}")
        task = replace(task, parts=int(parts))
        scenario = replace(scenario, task=task)
    n = task.parts
    capacity = bin_capacity(scenario)
    if n > capacity:
        raise ConfigError(
            f"task.parts = {n}, but {task.bin} holds {capacity} parts of "
            f"{scenario.pool_part_size:g} m that {task.robot} can reach (layers up to its rim)"
        )
    if scenario.spawner is not None:
        scenario = replace(
            scenario, spawner=replace(scenario.spawner, max_parts=n), part_pool=max(scenario.part_pool, n + 2)
        )
    return scenario  # checked where the cell is built from it (build_station)


class TaskRun:
    """A runtime with the task's controller, ready to advance (used by tests and notebooks).

    Use it as a context manager (``with TaskRun(...) as run:``) or call :meth:`close`
    to free the cell when done (an unclosed run stays in memory for the life of the
    process); a closed run refuses to advance.
    """

    def __init__(self, scenario: Scenario, *, meshcat=None):
        self.scenario = scenario
        task = scenario.required_task()
        added: list[PickAndPlaceController] = []

        def extend(builder, station):
            added.append(add_pick_and_place(builder, station, task)[0])

        self.runtime = FactoryRuntime(scenario, meshcat=meshcat, extend=extend, controlled=[task.robot])
        self.controller = added[0]
        rt = self.runtime
        conveyor = scenario.conveyor
        if conveyor is not None and conveyor.stop_on_beam and rt.station.break_beam is not None:
            # the counterpart of the beam's stop
            rt.driver.every(TASK_TICK, lambda: _restart_belt_when_beam_clears(rt))
        rt.driver.every(TASK_TICK, lambda: self._write_off_lost_parts(rt))

    def close(self) -> None:
        """Frees the cell (:meth:`FactoryRuntime.close`); what was read from it stays valid."""
        self.runtime.close()

    def __enter__(self) -> TaskRun:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _write_off_lost_parts(self, rt: FactoryRuntime) -> None:
        """A part the controller gave up on (lost, or fallen into the bin without a
        place) no longer holds the spawner back, and the spawner replaces it; once
        the controller stopped (the bin is full) the spawner stops too."""
        if self.control().mode is Mode.BIN_FULL:
            rt.auto_spawn = False
        for pick in self.history().picks:
            if pick.given_up and pick.part not in rt.pool.written_off and pick.part in rt.parts_in_world():
                rt.write_off_part(pick.part)

    def control(self) -> ControlState:
        """What the controller is doing now."""
        return control_of(self.controller, self.runtime.context)

    def history(self) -> PickHistory:
        """What the controller has done."""
        return history_of(self.controller, self.runtime.context)

    def done(self) -> bool:
        """The controller has placed the task's parts (and is back to waiting), or has
        stopped because the bin is full (and the arm is Home)."""
        control = self.control()
        if control.mode is Mode.BIN_FULL:
            return control.path.done(self.runtime.time)
        placed = sum(p.success for p in self.history().picks)
        return placed >= self.scenario.required_task().parts and control.mode in (Mode.HOME, Mode.WAIT_PART)


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
    :class:`omtp_drake.tasks.plots.RunRecorder`); ``on_chunk(run)`` after every chunk.
    With ``progress``, a progress bar shows simulated time and parts in the bin.
    The run's cell is closed (freed) before this returns, also when it raises.
    """
    scenario = prepare(scenario, seed=seed, parts=parts)
    task = scenario.required_task()
    n = task.parts
    limit = check_duration("--duration", duration if duration is not None else 30.0 * n)
    viewer = start_meshcat(view_for(scenario)) if (meshcat or record) else None
    with TaskRun(scenario, meshcat=viewer) as run:
        rt = run.runtime
        if record:
            start_recording(rt.station.visualizer)
        if viewer is not None:
            add_visual_extras(rt, recording=bool(record))  # camera frusta, detection markers
        if on_start is not None:
            on_start(run)
        bar = _progress_bar(scenario.name, limit) if progress else None
        wall0 = time.perf_counter()
        _advance_until_done(run, limit, chunk, on_chunk, bar)
        wall = time.perf_counter() - wall0
        if bar is not None:
            bar.close()
        if record:
            save_recording(rt.station.visualizer, viewer, record)
        return _result(run, wall)


def _progress_bar(name: str, limit: float):
    """A tqdm bar of simulated time out of ``limit`` s."""
    from tqdm import tqdm

    return tqdm(
        total=round(limit, 1),
        desc=name,
        unit="sim s",
        bar_format="{desc} | {n:.1f}/{total:.0f} s simulated |{bar}| [{elapsed}<{remaining}]",
    )


def _advance_until_done(
    run: TaskRun, limit: float, chunk: float, on_chunk: Optional[Callable[[TaskRun], None]], bar
) -> None:
    """Advances ``run`` chunk by chunk until its task is done or ``limit`` s,
    calling ``on_chunk`` and updating ``bar`` (parts in the bin) after each chunk."""
    rt = run.runtime
    task = run.scenario.required_task()
    while rt.time < limit - 1e-9:
        rt.advance_to(min(limit, rt.time + chunk))
        if on_chunk is not None:
            on_chunk(run)
        if bar is not None:
            bar.n = round(rt.time, 1)
            bar.set_description_str(
                f"{run.scenario.name}: {rt.ledger().in_bin.get(task.bin, 0)}/{task.parts} in {task.bin}",
                refresh=False,
            )
            bar.refresh()
        if run.done():
            break


def _result(run: TaskRun, wall: float) -> TaskResult:
    """The verdict of a finished run: its picks (a pending drop included), ledger and faults."""
    rt = run.runtime
    scenario = run.scenario
    task = scenario.required_task()
    n = task.parts
    ledger = rt.ledger()
    picks = list(run.history().picks)
    pending = run.control().pending_drop
    if pending is not None:  # dropped, and not seen at rest again before the run ended
        picks.append(pending)
    return TaskResult(
        scenario=scenario.name,
        seed=scenario.seed,
        picks=picks,
        ledger=ledger,
        success=judge(picks, ledger, task.bin, n),
        sim_time_s=rt.time,
        wall_time_s=wall,
        bin=task.bin,
        parts=n,
        faults=[r.to_dict() for r in rt.faults.reports] if rt.faults is not None else [],
    )


def _mean_cycle(succeeded: int, mean_s: float) -> str:
    """The summary line's cycle time: the successes' mean, or that no pick finished yet (its
    mean is NaN, printed as ``nan s`` before)."""
    return f"mean cycle {mean_s:.2f} s" if succeeded else "no pick finished"
