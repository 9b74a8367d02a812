"""What grading a class in isolation costs: the sandbox per script, and a class on 2 workers.

    python bench/bench_grade.py [--repeats 5] [--class-size 40] [--workers 2]

1. One honest script (the assignment 3 example) run three ways, ``--repeats`` times each,
   one at a time: a bare ``ros-run`` subprocess (what ``grade`` ran before it isolated
   anything), ``grade_one`` with ``--sandbox none`` (copy of the folder, limits, guard,
   output capture, process watch) and with ``--sandbox bwrap``. The cost per script is the
   difference of the medians to the bare run (target: <= 0.3 s for bwrap).
2. ``grade`` on a class of ``--class-size`` copies of that script on ``--workers`` workers
   (bubblewrap when it works): runs per minute, cluster start included.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from omtp_drake.ros.grade import GradeSettings, grade_folder, grade_one
from omtp_drake.ros.isolation import Limits, bwrap_works

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "ros" / "lecture6_assignment3.py"
SCENARIO = "lecture6_assignment3"


def bare(script: Path) -> None:
    command = [sys.executable, "-m", "omtp_drake.ros.cli", "ros-run", str(script), "--scenario", SCENARIO, "-q"]
    subprocess.run(command, capture_output=True, check=True, cwd=script.parent)


def isolated(script: Path, sandbox: str) -> None:
    settings = GradeSettings(SCENARIO, limits=Limits(), sandbox=sandbox)
    grade = grade_one(str(script), settings)
    if grade.status != "ok":
        raise RuntimeError(f"{sandbox}: {grade.status}: {grade.message}")


def median_wall(fn, repeats: int) -> float:
    walls = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - start)
    return statistics.median(walls)


def bench_cost(repeats: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "student.py"
        shutil.copy(EXAMPLE, script)
        ways = {"bare ros-run": lambda: bare(script), "sandbox none": lambda: isolated(script, "none")}
        if bwrap_works():
            ways["sandbox bwrap"] = lambda: isolated(script, "bwrap")
        ways["bare ros-run"]()  # warm: the model cache, the page cache
        walls = {name: median_wall(fn, repeats) for name, fn in ways.items()}
    base = walls["bare ros-run"]
    for name, wall in walls.items():
        extra = "" if name == "bare ros-run" else f"  cost {wall - base:+.3f} s per script"
        print(f"{name:14s} median wall {wall:6.3f} s (of {repeats}){extra}")


def bench_class(size: int, workers: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "class"
        folder.mkdir()
        for i in range(size):
            shutil.copy(EXAMPLE, folder / f"student_{i:02d}.py")
        start = time.perf_counter()
        grades = grade_folder(folder, SCENARIO, workers=workers, sandbox="auto")
        wall = time.perf_counter() - start
    ok = sum(g.status == "ok" for g in grades)
    sandbox = grades[0].isolation["sandbox"]
    print(
        f"grade: {size} scripts on {workers} workers (sandbox {sandbox}) in {wall:.1f} s wall ({ok} ok): "
        f"{60 * size / wall:.1f} runs per minute (cluster start included)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--class-size", type=int, default=40)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    bench_cost(args.repeats)
    if args.class_size:
        bench_class(args.class_size, args.workers)


if __name__ == "__main__":
    main()
