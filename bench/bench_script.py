"""Overhead of the scripting layer's blocking calls over a bare advance of the same duration.

Scene: ``lecture6_assignment4`` (robot 2 next to bin 1), no parts, a Cell.
Moves: R2Home -> R2Place -> R2Home joint moves (planned first: planning is not timed
here, see bench_planning.py), executed with ``Arm.execute`` (contacts checked every
50 ms), and with a guard (``until``, checked every 10 ms). Bare: the same plans
started with ``execute(plan, wait=False)`` and the cell advanced by one
``runtime.advance_to`` over the same simulated time the blocking call took (the
same motion, so what differs is the blocking layer: its chunked advances, contact
checks, guard calls and settle check). Also printed: the cell held still for as
long (what the moving arm itself costs Drake).

Printed: wall per simulated second of each, and the overhead over the bare run in
percent. Best of a few interleaved repeats; no pass/fail. Target: overhead <= 10 %.

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
    labels = ("execute", "execute + guard", "bare advance_to")
    rows: dict[str, list[float]] = {label: [] for label in (*labels, "arm held still")}
    took: dict[str, float] = {}  # simulated time the blocking call took, per target
    for _ in range(args.repeats):
        for label in labels:
            sim = wall = 0.0
            for target in ("Place", "Home"):
                plan = arm.plan(target)
                t0, w0 = cell.time, time.perf_counter()
                if label == "bare advance_to":
                    arm.execute(plan, wait=False)
                    cell.runtime.advance_to(t0 + took[target])
                else:
                    arm.execute(plan, until=(lambda: False) if "guard" in label else None)
                    took[target] = cell.time - t0
                wall += time.perf_counter() - w0
                sim += cell.time - t0
            rows[label].append(wall / sim)
        t0, w0 = cell.time, time.perf_counter()
        cell.runtime.advance_to(t0 + sim)  # the arm at Home, holding still
        rows["arm held still"].append((time.perf_counter() - w0) / sim)
    bare = min(rows["bare advance_to"])
    print(f"{'':<18} {'wall ms / sim s':>16} {'median':>8} {'overhead':>9}")
    for label, values in rows.items():
        best = min(values)
        print(f"{label:<18} {1e3 * best:16.1f} {1e3 * statistics.median(values):8.1f} "
              f"{100 * (best - bare) / bare:8.1f} %")


if __name__ == "__main__":
    main()
