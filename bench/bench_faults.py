"""Fault campaign: pick and place while things go wrong, over many seeds.

    python bench/bench_faults.py [--seeds 50] [--workers 2] [--out /tmp/faults]

For ``fill_bin`` and ``lecture7_conveyor_pick``, every run gets four faults at
random times (drawn from the run's seed, over the task's first 80 % of its
nominal duration):

- a vacuum failure of the task's robot (0.5 s), at the first moment from its
  time on that the robot holds a part (so the part drops),
- a blackout of the pick camera (1 s),
- a belt stop (power 0, held for 2 s against the task's restart helper),
- a spawned part knocked off its spot (0.5-1.5 m/s, a random horizontal
  direction), at the first moment from its time on that a part rests on the
  floor or the belt.

Runs go through ``omtp_drake.batch.run_batch`` (Dask, local processes). Printed
per scenario: runs; runs with every part accounted for (``TaskResult.accounted_for``:
the ledger balances and each part left loose is one the controller recorded as
given up on, with where it lies); successful runs; failure reasons of the pick
attempts and of the runs.
"""

from __future__ import annotations

import argparse
import collections
import logging
import math
from typing import Optional

import numpy as np

from omtp_drake.batch import run_batch
from omtp_drake.errors import OmtpError
from omtp_drake.scenario import Scenario
from omtp_drake.sim.ledger import held_parts
from omtp_drake.tasks.run import TaskResult, TaskRun, run_task

_log = logging.getLogger("bench_faults")

#: Nominal simulated seconds per part, by scenario (faults fall in 80 % of it).
NOMINAL = {"fill_bin": 6.0, "lecture7_conveyor_pick": 9.0}


def schedule(scenario: str, seed: int, parts: int) -> dict[str, float]:
    """When each fault strikes in run ``seed`` (simulated seconds)."""
    rng = np.random.default_rng([seed, 4242])
    end = 0.8 * NOMINAL[scenario] * parts
    return {fault: float(rng.uniform(1.0, end)) for fault in ("vacuum", "blackout", "belt_stop", "knock")}


def faulty_run(scenario: Scenario, duration: Optional[float]) -> TaskResult:
    """``run_task`` with the four faults of :func:`schedule` injected (a batch run_fn)."""
    task = scenario.required_task()
    when = schedule(scenario.name, scenario.seed, task.parts)
    rng = np.random.default_rng([scenario.seed, 77])
    done: set[str] = set()

    def belt_stop(rt) -> None:  # holds the belt at 0 for 2 s (the task's helper restarts it)
        t0 = when["belt_stop"]
        if rt.station.conveyor is not None and t0 <= rt.time <= t0 + 2.0:
            if "belt_stop" not in done:
                _log.info("t=%.2f belt stopped for 2 s", rt.time)
                done.add("belt_stop")
            rt.set_conveyor_power(0.0)

    def start(run: TaskRun) -> None:
        run.runtime.on_tick(belt_stop)
        run.runtime.on_tick(lambda rt: inject(run))

    def inject(run: TaskRun) -> None:
        rt = run.runtime
        if "vacuum" not in done and rt.time >= when["vacuum"] and task.robot in held_parts(rt.station, rt.context):
            rt.fail_vacuum(task.robot, 0.5)
            done.add("vacuum")
            _log.info("t=%.2f vacuum of %s fails", rt.time, task.robot)
        if "blackout" not in done and rt.time >= when["blackout"]:
            rt.black_out_camera(task.camera, 1.0)
            done.add("blackout")
            _log.info("t=%.2f %s blacked out", rt.time, task.camera)
        if "knock" not in done and rt.time >= when["knock"]:
            loose = [n for n, place in rt.ledger().parts.items() if place in ("on_floor", "on_belt")]
            if loose:  # otherwise: the next tick
                angle = rng.uniform(0.0, 2 * math.pi)
                speed = rng.uniform(0.5, 1.5)
                rt.knock_part(loose[-1], [speed * math.cos(angle), speed * math.sin(angle), 0.0])
                done.add("knock")
                _log.info("t=%.2f %s knocked at %.2f m/s", rt.time, loose[-1], speed)

    return run_task(scenario, duration=duration, on_start=start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default=None, help="results folder (resumes)")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    for name in NOMINAL:
        out = f"{args.out}/{name}" if args.out else None
        try:
            records = run_batch(name, range(args.seeds), workers=args.workers, out=out, run_fn=faulty_run,
                                progress=False)
        except OmtpError as e:
            print(f"{name}: {e}")
            continue
        finished = [r for r in records if r.result is not None]
        ok = [r for r in finished if r.result.accounted_for]
        picks = collections.Counter(p.reason for r in finished for p in r.result.picks if not p.success)
        runs = collections.Counter(r.failure_reason for r in records if not r.success)
        print(f"{name}: {len(records)} runs ({args.seeds} seeds, 4 faults each)")
        print(f"  every part accounted for: {len(ok)}/{len(records)}"
              f" (not: seeds {[r.seed for r in finished if not r.result.accounted_for] or 'none'})")
        print(f"  succeeded: {sum(r.success for r in records)}/{len(records)}")
        print(f"  failed pick attempts by reason: {dict(picks) or 'none'}")
        print(f"  runs not succeeding, by reason: {dict(runs) or 'none'}")
        cycles = [p.cycle_time for r in finished for p in r.result.picks if p.success]
        if cycles:
            print(f"  cycle of successful picks: mean {np.mean(cycles):.2f} s, worst {max(cycles):.2f} s")


if __name__ == "__main__":
    main()
