"""What grading a class in isolation costs: the sandbox per script, and a class on 2 workers.

    python bench/bench_grade.py [--repeats 9] [--class-size 40] [--workers 2]

1. One honest script (the assignment 3 example) run three ways, interleaved, ``--repeats``
   times each: a bare ``ros-run`` subprocess (what ``grade`` ran before it isolated
   anything), ``grade_one`` with ``--sandbox none`` (copy of the folder, limits, guard,
   output capture, process watch) and with ``--sandbox bwrap``. The cost per script is the
   difference of the medians to the bare run (target: <= 0.3 s for bwrap); and
   bubblewrap's own start (``bwrap ... true`` against ``true``).
2. ``grade`` on a class of ``--class-size`` scripts on ``--workers`` workers, every other one
   that script and every other one a MoveIt script (tests/fixtures/grade_class/move_home.py:
   robot 1 to a named state), ``--moveit melodic`` as the course's class, with bubblewrap (when it works)
   and with ``--sandbox none``: runs per minute, cluster start included, the rows holding
   refusals, and whether the rows are the same but for the sandbox line.
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

from omtp_drake.grading.grade import Grade, GradeSettings, grade_folder, grade_one
from omtp_drake.grading.isolation import Limits, bwrap_works, sandbox_prefix

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "ros" / "lecture6_assignment3.py"
#: The class's MoveIt half: a student's moveit_commander script (robot 1 to a named state).
MOVE_HOME = ROOT / "tests" / "fixtures" / "grade_class" / "move_home.py"
SCENARIO = "lecture6_assignment3"


def bare(script: Path) -> None:
    command = [
        sys.executable,
        "-m",
        "omtp_drake.grading.cli",
        "ros-run",
        str(script),
        "--scenario",
        SCENARIO,
        "-q",
    ]
    subprocess.run(command, capture_output=True, check=True, cwd=script.parent)


def isolated(script: Path, sandbox: str) -> None:
    settings = GradeSettings(SCENARIO, limits=Limits(), sandbox=sandbox)
    grade = grade_one(str(script), settings)
    if grade.status != "ok":
        raise RuntimeError(f"{sandbox}: {grade.status}: {grade.message}")


def bench_cost(repeats: int) -> None:
    """The three ways interleaved, round by round (the machine's load drifts)."""
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "student.py"
        shutil.copy(EXAMPLE, script)
        ways = {"bare ros-run": lambda: bare(script), "sandbox none": lambda: isolated(script, "none")}
        if bwrap_works():
            ways["sandbox bwrap"] = lambda: isolated(script, "bwrap")
        ways["bare ros-run"]()  # warm: the model cache, the page cache
        walls: dict[str, list[float]] = {name: [] for name in ways}
        for _ in range(repeats):
            for name, fn in ways.items():
                start = time.perf_counter()
                fn()
                walls[name].append(time.perf_counter() - start)
        if bwrap_works():
            work = Path(tmp)
            walls["bwrap alone"] = [_wall([*sandbox_prefix(work, work), "true"]) for _ in range(20)]
            walls["no bwrap"] = [_wall(["true"]) for _ in range(20)]
    base = statistics.median(walls["bare ros-run"])
    for name in ways:
        wall = statistics.median(walls[name])
        extra = "" if name == "bare ros-run" else f"  cost {wall - base:+.3f} s per script"
        print(f"{name:14s} median wall {wall:6.3f} s (of {repeats}){extra}")
    if "bwrap alone" in walls:
        alone = statistics.median(walls["bwrap alone"]) - statistics.median(walls["no bwrap"])
        print(f"bubblewrap's own start (bwrap ... true against true, median of 20): {1000 * alone:.1f} ms")


def _wall(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True)
    return time.perf_counter() - start


def bench_class(size: int, workers: int) -> None:
    """The class graded with bubblewrap and with ``--sandbox none`` (``--moveit melodic``, as
    the course's class): wall times, and the rows, which must be the same but for the sandbox
    (and the runs' wall times)."""
    sandboxes = ["bwrap", "none"] if bwrap_works() else ["none"]
    rows: dict[str, list[tuple]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "class"
        folder.mkdir()
        for i in range(size):
            shutil.copy(MOVE_HOME if i % 2 else EXAMPLE, folder / f"student_{i:02d}.py")
        for sandbox in sandboxes:
            start = time.perf_counter()
            grades = grade_folder(
                folder, SCENARIO, workers=workers, sandbox=sandbox, options={"moveit": "melodic"}
            )
            wall = time.perf_counter() - start
            rows[sandbox] = [_row(g) for g in grades]
            ok = sum(g.status == "ok" for g in grades)
            refused = sum(bool(g.refused) for g in grades)
            print(
                f"grade: {size} scripts on {workers} workers, sandbox {sandbox}: {wall:.1f} s wall ({ok} ok, "
                f"{refused} with refusals): {60 * size / wall:.1f} runs per minute (cluster start included)"
            )
    if len(rows) == 2:
        same = "identical" if rows["bwrap"] == rows["none"] else "DIFFERENT"
        print(f"rows of bwrap and none: {same} (all but the sandbox and the wall times)")


def _row(grade: Grade) -> tuple:
    """A grade's row without its sandbox and wall time."""
    report = grade.report or {}
    return (grade.script, grade.status, grade.in_bins, grade.message, grade.refused, report.get("sim_time_s"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--class-size", type=int, default=40)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    if args.repeats:
        bench_cost(args.repeats)
    if args.class_size:
        bench_class(args.class_size, args.workers)


if __name__ == "__main__":
    main()
