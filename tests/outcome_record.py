"""What a user sees of a pick-and-place run, recorded so that two versions of the code can
be compared (issue 46's equivalence: outcomes, ledgers, cycle times, the tool path at the
machine's decisions), without asking for bit-identical floats.

:func:`record` runs a built-in scenario's task with ``run_task`` and returns a plain dict
(JSON): the verdict, the ledger (which part where), each pick (part, success, cycle time),
and every decision point of the pick-and-place machine: the time it changed its mode or
its tool path, the new mode, and the measured tool (cup face) position ``p_WT`` there.

A decision at time ``t`` is taken by the controller's update at ``t``, which reads the
plant's state at ``t``; the run advances in steps of the controller's period, so the pose
recorded at the step that ends at ``t`` is the one the machine decided on.

Used by ``tests/golden/record_outcomes.py`` (writes ``tests/golden/outcomes_before.json``)
and ``tests/test_equivalence.py`` (compares a run with it).
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.tasks.run import TaskResult, TaskRun, prepare, run_task

#: The scenarios the equivalence test compares (each is a run the suite makes anyway).
SCENARIOS = ("fill_bin", "lecture6_assignment4", "lecture7_conveyor_pick")
#: Also recorded (the FlexBE lecture's cell run by the pick-and-place task).
EXTRA_SCENARIOS = ("lecture7_flexbe",)


class DecisionRecorder:
    """``on_chunk`` of a run advanced in steps of the controller's period: the tool's
    measured position at every step, and a decision wherever the control state's mode
    or path changed."""

    def __init__(self) -> None:
        self.decisions: list[dict[str, Any]] = []
        self.belt_powers: set[float] = set()
        self._p_WT: dict[int, list[float]] = {}
        self._last: Optional[tuple[Any, Any]] = None
        self._period = 0.05
        self._tip: Any = None

    def start(self, run: TaskRun) -> None:
        task = run.scenario.required_task()
        self._period = 1.0 / task.update_rate_hz
        station = run.runtime.station
        gripper = run.scenario.robot(task.robot).gripper
        self._tip = station.plant.GetFrameByName(f"{gripper}_tip")
        self(run)

    def _key(self, t: float) -> int:
        return round(t / self._period)

    def __call__(self, run: TaskRun) -> None:
        rt = run.runtime
        plant = rt.station.plant
        p = self._tip.CalcPoseInWorld(plant.GetMyContextFromRoot(rt.context)).translation()
        self._p_WT[self._key(rt.time)] = [float(x) for x in p]
        self.belt_powers.add(rt.conveyor_power())
        control = run.control()
        if self._last is None or control.mode is not self._last[0] or control.path is not self._last[1]:
            decided = self._decision_time(control, rt.time)
            self.decisions.append(
                {"t": round(decided, 6), "mode": control.mode.value, "p_WT": self._p_WT[self._key(decided)]}
            )
            self._last = (control.mode, control.path)

    def _decision_time(self, control, now: float) -> float:
        """When the change seen now was decided: the mode's start if the mode changed,
        else the start of the new path's first segment (a path starts where it is
        decided)."""
        if self._last is None or control.mode is not self._last[0]:
            return control.mode_start
        segments = control.path.segments
        return segments[0].t0 if segments and segments[0].t0 <= now + 1e-9 else now


def run_and_record(name: str, seed: int = 0) -> tuple[TaskResult, dict[str, Any]]:
    """``run_task(name, seed=seed)``'s result and its record (see the module doc)."""
    recorder = DecisionRecorder()
    scenario = prepare(name, seed=seed)
    period = 1.0 / scenario.required_task().update_rate_hz
    result = run_task(scenario, chunk=period, on_start=recorder.start, on_chunk=recorder)
    return result, {
        "scenario": name,
        "seed": seed,
        "success": result.success,
        "ledger": dict(sorted(result.ledger.parts.items())),
        "in_bin": dict(result.ledger.in_bin),
        "picks": [
            {"part": p.part, "success": p.success, "attempt": p.attempt, "cycle_time": p.cycle_time}
            for p in result.picks
        ],
        "mean_cycle_time_s": result.summary["mean_cycle_time_s"],
        "sim_time_s": result.sim_time_s,
        "belt_powers": sorted(recorder.belt_powers),
        "decisions": recorder.decisions,
    }


def record(name: str, seed: int = 0) -> dict[str, Any]:
    """The record of ``run_task(name, seed=seed)`` (see the module doc)."""
    return run_and_record(name, seed)[1]
