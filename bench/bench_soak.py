"""Soak of the batch runner (issue 14): many seeds, the summary per batch.

    python bench/bench_soak.py [--workers 2] [--out /tmp/soak] [--scale 1.0]

Three batches on a local Dask cluster (``omtp_drake.batch.run_batch``):

- ``fill_bin`` (10 parts), seeds 0-99;
- ``lecture7_conveyor_pick``, seeds 0-49;
- ``fill_bin`` with a vacuum failure mid-transfer, seeds 0-49: in pick number
  (seed mod 10) + 1, once the transfer is half done, the robot's vacuum fails for
  0.5 s and the part drops wherever the arm is.

Printed for each: the batch summary (success rate with its Wilson interval, cycle
times, failure reasons, ledger anomalies), runs that crashed, errored or timed out,
and parts unaccounted for (``TaskResult.accounted_for``). ``--scale`` shrinks the seed
counts for a quick look.
"""

from __future__ import annotations

import argparse
import logging
from typing import Optional

from omtp_drake.batch import format_summary, run_batch, summarize
from omtp_drake.control.pick_and_place import Mode
from omtp_drake.scenario import Scenario
from omtp_drake.tasks.run import TaskResult, TaskRun, run_task


def vacuum_failure_mid_transfer(scenario: Scenario, duration: Optional[float]) -> TaskResult:
    """``run_task`` with the task robot's vacuum failing half-way through one transfer."""
    task = scenario.required_task()
    target = scenario.seed % task.parts + 1  # which pick (1-based) loses its part
    state = {"transfers": 0, "in_transfer": False, "done": False}

    def watch(run: TaskRun) -> None:
        control = run.control()
        if control.mode is not Mode.TRANSFER:
            state["in_transfer"] = False
            return
        if not state["in_transfer"]:
            state["in_transfer"] = True
            state["transfers"] += 1
        half = 0.5 * (control.mode_start + control.path.end_time)
        if not state["done"] and state["transfers"] == target and run.runtime.time >= half:
            run.runtime.fail_vacuum(task.robot, 0.5)
            state["done"] = True

    return run_task(scenario, duration=duration, on_start=lambda run: run.runtime.on_tick(lambda rt: watch(run)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default=None, help="results folder (resumes)")
    parser.add_argument("--scale", type=float, default=1.0, help="fraction of the seed counts")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    batches = [
        ("fill_bin", 100, None, "fill_bin"),
        ("lecture7_conveyor_pick", 50, None, "lecture7_conveyor_pick"),
        ("fill_bin", 50, vacuum_failure_mid_transfer, "fill_bin_vacuum_failure"),
    ]
    for scenario, seeds, run_fn, label in batches:
        n = max(1, round(seeds * args.scale))
        out = f"{args.out}/{label}" if args.out else None
        kwargs = {"run_fn": run_fn} if run_fn else {}
        records = run_batch(scenario, range(n), workers=args.workers, out=out, progress=False, **kwargs)
        print(f"== {label}: seeds 0-{n - 1}")
        print(format_summary(summarize(records)))
        bad = {s: [r.seed for r in records if r.status == s] for s in ("crashed", "error", "timeout")}
        print(f"  crashed / error / timeout: {', '.join(f'{k} {v or 0}' for k, v in bad.items())}")
        lost = {r.seed: r.result.unaccounted_parts for r in records if r.result and not r.result.accounted_for}
        count = sum(max(1, len(v)) for v in lost.values())  # (an unbalanced ledger counts one)
        print(f"  runs with parts unaccounted for: {len(lost)}, parts: {count} (seeds: {sorted(lost) or 'none'})",
              flush=True)


if __name__ == "__main__":
    main()
