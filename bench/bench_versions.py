"""Two checkouts side by side: the same cases, interleaved, each run in a child process
importing ``omtp_drake`` from its checkout (issue 38's before/after table).

    python bench/bench_versions.py BEFORE AFTER [--rounds 3] [--cases fill_bin,belt,...]

BEFORE and AFTER are source checkouts (e.g. a ``git worktree`` of the base commit and
this one). Cases: ``fill_bin`` and ``lecture7_conveyor_pick`` (``run_task``, seed 0),
``belt`` (``lecture7_conveyor`` with 10 parts riding, 10 s, as ``omtp-drake bench``),
``ros-run`` (``examples/ros/lecture6_assignment4.py``, 2 parts) and ``flexbe`` (the
Conveyor Pick behaviour of ``examples/flexbe``, 2 parts). Each round runs every case
once in each checkout, alternating which goes first. Printed per case and checkout:
wall and process CPU milliseconds per simulated second (best and median of the
rounds), the simulated time and the outcome (which must not differ), and the load
average at the start and the end. No pass/fail; numbers only.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

#: The child: imports omtp_drake from ROOT (not the installed one), runs CASE, prints JSON.
CHILD = r"""
import json, logging, os, sys, time
root = sys.argv[1]
sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f)]
sys.path[:0] = [root, os.path.join(root, "bench")]
logging.disable(logging.WARNING)
import omtp_drake
assert omtp_drake.__file__.startswith(root), omtp_drake.__file__
case, root = sys.argv[2], os.path.abspath(root)
cpu, wall = time.process_time(), time.perf_counter()
if case in ("fill_bin", "lecture7_conveyor_pick"):
    from omtp_drake.tasks.run import run_task
    r = run_task(case, seed=0)
    sim, outcome = r.sim_time_s, f"{r.summary['succeeded']}/{r.summary['attempted']} picks"
elif case == "belt":
    from speed import belt_scenario
    from omtp_drake.sim.runtime import FactoryRuntime
    rt = FactoryRuntime(belt_scenario(10))
    cpu, wall = time.process_time(), time.perf_counter()
    rt.advance_to(10.0)
    sim, outcome = 10.0, str(rt.ledger().on_belt) + " on the belt"
elif case == "ros-run":
    from omtp_drake.ros import run_script
    r = run_script(os.path.join(root, "examples/ros/lecture6_assignment4.py"), ["2"], scenario="lecture6_assignment4")
    sim, outcome = r.sim_time_s, f"{r.in_bins} in bins"
elif case == "flexbe":
    from omtp_drake.ros.flexbe import run_behavior
    r = run_behavior("Conveyor Pick", [os.path.join(root, "examples/flexbe")], scenario="lecture7_flexbe",
                     params={"parts": "2"})
    sim, outcome = r.sim_time_s, f"{r.outcome}, bin_2: {r.ledger['in_bin']['bin_2']}"
else:
    raise SystemExit(f"unknown case {case}")
cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
print(json.dumps({"cpu": cpu / sim, "wall": wall / sim, "sim": round(sim, 3), "outcome": outcome}))
"""

CASES = ("fill_bin", "lecture7_conveyor_pick", "belt", "ros-run", "flexbe")


def run(root: Path, case: str) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", CHILD, str(root), case], capture_output=True, text=True, check=False
    )
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode != 0 or not lines:
        raise SystemExit(f"{case} in {root} failed:\n{done.stderr[-2000:]}")
    return json.loads(lines[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cases", default=",".join(CASES))
    args = parser.parse_args()
    roots = {"before": args.before.resolve(), "after": args.after.resolve()}
    cases = args.cases.split(",")
    print(f"load average at the start: {os.getloadavg()}", flush=True)
    results: dict[tuple[str, str], list[dict]] = {(c, v): [] for c in cases for v in roots}
    for k in range(args.rounds):
        for case in cases:
            order = list(roots) if k % 2 == 0 else list(reversed(roots))
            for version in order:
                results[case, version].append(run(roots[version], case))
                r = results[case, version][-1]
                print(f"  round {k + 1} {case:24s} {version:6s} wall {1e3 * r['wall']:6.1f}  "
                      f"CPU {1e3 * r['cpu']:6.1f} ms/s", flush=True)
    print(f"load average at the end: {os.getloadavg()}")
    print("| case | version | wall ms/s best (median) | CPU ms/s best (median) | simulated s | outcome |")
    print("|---|---|---:|---:|---:|---|")
    for case in cases:
        for version in roots:
            rows = results[case, version]
            walls, cpus = [1e3 * r["wall"] for r in rows], [1e3 * r["cpu"] for r in rows]
            sims, outcomes = sorted({r["sim"] for r in rows}), sorted({r["outcome"] for r in rows})
            print(f"| {case} | {version} | {min(walls):.1f} ({statistics.median(walls):.1f}) | "
                  f"{min(cpus):.1f} ({statistics.median(cpus):.1f}) | {sims} | {outcomes} |")


if __name__ == "__main__":
    main()
