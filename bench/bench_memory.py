"""Memory of a long-lived process that builds the cell again and again.

Three loops, each in a fresh child process (so one loop's memory is not the next's):

- ``cell``: ``with Cell("lecture6_assignment4"): pass``, N times (default 100);
- ``task``: ``run_task("lecture6_assignment4", parts=1)``, a full pick and place
  (6 s simulated, 2-3 s wall each), N times (default 100);
- ``ros``: ``run_script`` (what ``omtp-drake ros-run`` runs) of
  ``examples/ros/lecture6_assignment3.py``, N times (default 30).

After each iteration ``gc.collect()`` runs (the diagrams are freed by Python's cycle
collector; without it they go at its next full collection: ``--no-collect`` shows
that curve). Printed per loop: the resident memory (VmRSS of /proc/self/status)
after the imports and after iterations 1, 2, 5, 10, 20, ... N; the first
iteration's own cost (RSS after it minus RSS after the imports: imports done
lazily by the first build count there); the growth over the N - 1 later
iterations and its ratio to the first cost (target for ``cell``: below 1); the
Python heap's growth (``sys.getallocatedblocks``) over the same span; and the
RSS after ``malloc_trim(0)`` at the end (glibc: what is still held rather than
kept by the allocator). Numbers only, no pass/fail.

    python bench/bench_memory.py [--cells 100] [--tasks 100] [--ros 30] [--no-collect]
    python bench/bench_memory.py --only cell --n 20      # one loop, in this process
"""

from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import gc
import logging
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
ROS_SCRIPT = REPO / "examples" / "ros" / "lecture6_assignment3.py"


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def trimmed_rss_mb() -> float:
    """RSS after glibc hands its free pages back (plain RSS where there is no glibc)."""
    name = ctypes.util.find_library("c")
    if name is not None:
        libc = ctypes.CDLL(name)
        if hasattr(libc, "malloc_trim"):
            libc.malloc_trim(0)
    return rss_mb()


def _iteration(loop: str):
    """The loop's one iteration, imports done."""
    if loop == "cell":
        from omtp_drake import Cell

        def build() -> None:
            with Cell("lecture6_assignment4"):
                pass

        return build
    if loop == "task":
        from omtp_drake import run_task

        return lambda: run_task("lecture6_assignment4", parts=1)
    if loop == "ros":
        import contextlib
        import io

        from omtp_drake.ros import run_script

        def session() -> None:
            with contextlib.redirect_stdout(io.StringIO()):
                report = run_script(ROS_SCRIPT, scenario="lecture6_assignment3", timeout=30.0)
            if report.exception is not None:
                raise RuntimeError(f"{ROS_SCRIPT.name} failed: {report.exception}")

        return session
    raise SystemExit(f"--only {loop!r} is unknown; valid: cell, task, ros")


def run_loop(loop: str, n: int, collect: bool) -> None:
    """Runs one loop here and prints its line."""
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    logging.getLogger("rospy").setLevel(logging.ERROR)
    step = _iteration(loop)
    gc.collect()
    base, curve, blocks = rss_mb(), {}, {}
    wall = time.perf_counter()
    for i in range(1, n + 1):
        step()
        if collect:
            gc.collect()
        if i in (1, 2, 5, n) or i % 10 == 0:
            curve[i] = rss_mb()
            blocks[i] = sys.getallocatedblocks()
    wall = (time.perf_counter() - wall) / n
    first = curve[1] - base
    growth = curve[n] - curve[1]
    points = " ".join(f"{i}:{mb:.0f}" for i, mb in curve.items())
    ratio = growth / first if first > 0 else float("nan")
    print(
        f"{loop:5s} n={n:3d} {wall:5.2f} s each | RSS MB after imports {base:.0f}, after i: {points} | "
        f"first {first:5.1f} MB, growth over {n - 1} more {growth:6.1f} MB "
        f"({growth / max(n - 1, 1):5.2f}/iter, {ratio:.2f} x first) | "
        f"Python heap {blocks[n] - blocks[1]:+d} blocks | after malloc_trim {trimmed_rss_mb():.0f} MB",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100, help="Cell builds and closes (default 100)")
    parser.add_argument("--tasks", type=int, default=100, help="run_task runs (default 100)")
    parser.add_argument("--ros", type=int, default=30, help="ros-run sessions (default 30)")
    parser.add_argument("--no-collect", action="store_true", help="no gc.collect() between iterations")
    parser.add_argument("--only", help="run one loop (cell, task, ros) in this process")
    parser.add_argument("--n", type=int, default=20, help="iterations of --only (default 20)")
    args = parser.parse_args()
    if args.only:
        run_loop(args.only, args.n, not args.no_collect)
        return
    flags = ["--no-collect"] if args.no_collect else []
    for loop, n in (("cell", args.cells), ("task", args.tasks), ("ros", args.ros)):
        if n > 0:
            subprocess.run([sys.executable, __file__, "--only", loop, "--n", str(n), *flags], check=True)


if __name__ == "__main__":
    main()
