"""Overhead of the scripting layer's blocking calls over a bare advance of the same duration.

Scene: ``lecture6_assignment4`` (robot 2 next to bin 1), no parts, a Cell.
Moves: R2Home -> R2Place -> R2Home joint moves (planned first: planning is not timed
here, see bench_planning.py), executed with ``Arm.execute`` (contacts checked every
50 ms), and with a guard (``until``, checked every 10 ms). Bare: the same cell
advanced by ``runtime.advance_to`` for the same simulated time, the arm holding
still (the same diagram: the commanders sample at 100 Hz either way).

Printed: wall per simulated second of each, and the overhead in percent. Best
of a few repeats; no pass/fail. Target: overhead <= 10 %.

    python bench/bench_script.py [--repeats 5]
"""

import argparse
import logging
import statistics
import time

from omtp_drake import Cell

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    cell = Cell("lecture6_assignment4", auto_spawn=False)
    arm = cell.arm("robot2")
    arm.go("Home")
    rows: dict[str, list[float]] = {"execute": [], "execute + guard": [], "bare advance_to": []}
    for _ in range(args.repeats):
        for label in ("execute", "execute + guard"):
            sim = wall = 0.0
            for target in ("Place", "Home"):
                plan = arm.plan(target)
                t0, w0 = cell.time, time.perf_counter()
                arm.execute(plan, until=(lambda: False) if "guard" in label else None)
                wall += time.perf_counter() - w0
                sim += cell.time - t0
            rows[label].append(wall / sim)
        t0, w0 = cell.time, time.perf_counter()
        cell.runtime.advance_to(t0 + sim)
        rows["bare advance_to"].append((time.perf_counter() - w0) / sim)
    bare = min(rows["bare advance_to"])
    print(f"{'':<18} {'wall ms / sim s':>16} {'median':>8} {'overhead':>9}")
    for label, values in rows.items():
        best = min(values)
        print(f"{label:<18} {1e3 * best:16.1f} {1e3 * statistics.median(values):8.1f} "
              f"{100 * (best - bare) / bare:8.1f} %")


if __name__ == "__main__":
    main()
