"""Fault campaign: pick and place while things go wrong, over many seeds.

    python bench/bench_faults.py [--seeds 50] [--workers 2] [--out /tmp/faults]

For ``fill_bin`` and ``lecture7_conveyor_pick``, every run declares four faults
in its scenario's ``faults:`` (omtp_drake.scenario.faults), drawn from the run's
seed over the task's first 80 % of its nominal duration:

- a vacuum failure of the task's robot (0.5 s) during its k-th hold of a part
  (k random), 0-1 s after the attach (so the part drops),
- a blackout of the pick camera (1 s) at a random time,
- a belt stop (power 0, held for 2 s against the task's restart helper),
- the part that came to rest last knocked off its spot (0.5-1.5 m/s, a random
  horizontal direction) at a random time (nothing, if none rests then).

Each run's result lists what each fault did (``TaskResult.faults``).

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
from dataclasses import replace
from typing import Optional

import numpy as np

from omtp_drake.batch import run_batch
from omtp_drake.errors import OmtpError
from omtp_drake.scenario import FaultConfig, Scenario
from omtp_drake.tasks import TaskResult, run_task

_log = logging.getLogger("bench_faults")

#: Nominal simulated seconds per part, by scenario (faults fall in 80 % of it).
NOMINAL = {"fill_bin": 6.0, "lecture7_conveyor_pick": 9.0}


def schedule(scenario: Scenario) -> list[FaultConfig]:
    """The run's four faults, as scenario data (drawn from the run's seed)."""
    task = scenario.required_task()
    rng = np.random.default_rng([scenario.seed, 4242])
    end = 0.8 * NOMINAL[scenario.name] * task.parts
    angle, speed = rng.uniform(0.0, 2 * math.pi), rng.uniform(0.5, 1.5)
    return [
        # The vacuum fails while the robot holds a part: during the k-th hold, after 0-1 s.
        FaultConfig(name="vacuum", kind="vacuum_failure", robot=task.robot, event="holding",
                    count=int(rng.integers(1, task.parts + 1)), after=float(rng.uniform(0.0, 1.0)),
                    duration=0.5),
        FaultConfig(name="blackout", kind="camera_blackout", camera=task.camera,
                    at=float(rng.uniform(1.0, end)), duration=1.0),
        FaultConfig(name="belt_stop", kind="belt_stop", at=float(rng.uniform(1.0, end)), duration=2.0),
        # The part that came to rest last is knocked (nothing, if none rests then).
        FaultConfig(name="knock", kind="part_knocked", at=float(rng.uniform(1.0, end)),
                    velocity=[speed * math.cos(angle), speed * math.sin(angle), 0.0]),
    ]


def faulty_run(scenario: Scenario, duration: Optional[float]) -> TaskResult:
    """``run_task`` with the four faults of :func:`schedule` declared in the scenario (a batch run_fn)."""
    return run_task(replace(scenario, faults=schedule(scenario)), duration=duration)


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
        struck = collections.Counter(f["name"] for r in finished for f in r.result.faults)
        dropped = sum(1 for r in finished for f in r.result.faults if f["effect"].get("dropped"))
        print(f"  faults struck: {dict(struck) or 'none'}; parts dropped by the vacuum failure: {dropped}")
        print(f"  failed pick attempts by reason: {dict(picks) or 'none'}")
        print(f"  runs not succeeding, by reason: {dict(runs) or 'none'}")
        cycles = [p.cycle_time for r in finished for p in r.result.picks if p.success]
        if cycles:
            print(f"  cycle of successful picks: mean {np.mean(cycles):.2f} s, worst {max(cycles):.2f} s")


if __name__ == "__main__":
    main()
