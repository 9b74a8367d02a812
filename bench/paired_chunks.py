"""Two variants of one run, advanced side by side in one process (issue 46): a small
cost difference measured on a busy machine.

    python bench/paired_chunks.py [scenario] [--chunk 1.0] [--until 60]

Builds the scenario's task run twice: ``old``, the arm's jerk hold sampling at ``h / 2``
past the controller's updates (as before 2026-11-29), and ``new``, at the updates
themselves (``omtp_drake.control.joint_plan.JerkStream``). The two give the same run,
bit for bit (checked here: the plant's positions after every chunk). It advances each
by ``--chunk`` simulated seconds in turn (old first in every other pair: the second of
a pair runs on caches the first warmed, about 5 % cheaper here), timing each chunk's thread CPU, so both see
the same load within a fraction of a second; it prints the simulator's steps and the
median, total and least CPU per simulated second of each, and the paired ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from pydrake.systems.primitives import ZeroOrderHold

from omtp_drake.control import joint_plan
from omtp_drake.tasks.run import TaskRun, prepare


def _build(scenario: str, old: bool) -> TaskRun:
    """The task run, with the hold at ``h / 2`` past the updates when ``old``."""
    task = prepare(scenario).required_task()
    h = 1.0 / task.diffik_rate_hz
    if old:
        joint_plan.ZeroOrderHold = lambda period, n: ZeroOrderHold(period, n, h / 2)
    try:
        return TaskRun(prepare(scenario))
    finally:
        joint_plan.ZeroOrderHold = ZeroOrderHold


def advance_in_pairs(
    runs: dict[str, TaskRun], chunk: float, until: float
) -> tuple[dict[str, list[float]], float]:
    """Advances the two ``runs`` by ``chunk`` simulated seconds in turn up to ``until`` (which
    goes first alternating), checking after each pair that their plants' positions are equal;
    (thread CPU of each chunk by run, the time reached)."""
    names = list(runs)
    cpu: dict[str, list[float]] = {name: [] for name in runs}
    t, pairs = 0.0, 0
    while t < until - 1e-9:
        t, pairs = min(t + chunk, until), pairs + 1
        q = []
        for name in names if pairs % 2 else names[::-1]:
            run = runs[name]
            start = time.thread_time()
            run.runtime.advance_to(t)
            cpu[name].append(time.thread_time() - start)
            plant = run.runtime.station.plant
            q.append(plant.GetPositions(plant.GetMyContextFromRoot(run.runtime.context)))
        if not np.array_equal(q[0], q[1]):
            raise SystemExit(f"the two runs differ at {t:g} s")
    return cpu, t


def pair_arguments(doc: str) -> argparse.Namespace:
    """A paired-chunk script's command line: the scenario, the chunk and the end (simulated s);
    the script's doc's first paragraph as its description."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("scenario", nargs="?", default="fill_bin")
    parser.add_argument("--chunk", type=float, default=1.0)
    parser.add_argument("--until", type=float, default=60.0)
    return parser.parse_args()


def main() -> None:
    args = pair_arguments(__doc__)
    runs = {"old": _build(args.scenario, old=True), "new": _build(args.scenario, old=False)}
    cpu, t = advance_in_pairs(runs, args.chunk, args.until)
    for name, run in runs.items():
        seconds = cpu[name]
        print(
            f"{name}: steps {run.runtime.simulator.get_num_steps_taken()}, CPU ms per simulated s: "
            f"median {1e3 * statistics.median(seconds) / args.chunk:.1f}, "
            f"total {1e3 * sum(seconds) / t:.1f}, least {1e3 * min(seconds) / args.chunk:.1f}"
        )
    ratios = [n / o for o, n in zip(cpu["old"], cpu["new"])]
    print(f"new / old, chunk by chunk: median {statistics.median(ratios):.3f} ({len(ratios)} chunks)")


if __name__ == "__main__":
    main()
