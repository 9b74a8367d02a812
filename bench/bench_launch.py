"""Building the cell from a student's files (the course-layout launch of tests/fixtures)
against building it from the built-in scenario: CPU time (this process's) and wall time of
each, interleaved, the ratios (target <= 1.5x) and the load average before and after. Each
build is the scenario (read from the launch, or loaded) plus the runtime the commands build
on it (station, diagram, context). CPU time is the figure to compare on a shared machine:
wall time grows with the load, CPU time much less.

    python bench/bench_launch.py [--repeats 5] [--cold 3]

With ``--cold N``, N more pairs of fresh processes (interleaved) time each path's first
build in its process (the modules imported first, nothing built): what one command sees.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WORKSPACE = ROOT / "tests" / "fixtures" / "catkin_ws" / "src"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


def build_from_launch() -> tuple[float, float, float]:
    """(wall s, CPU s, CPU s of reading the files) of one build."""
    from omtp_drake.launch import own_cell
    from omtp_drake.sim.runtime import FactoryRuntime

    start, cpu = time.perf_counter(), time.process_time()
    scenario = own_cell(LAUNCH, workspace=[WORKSPACE]).scenario
    read = time.process_time() - cpu
    FactoryRuntime(scenario).close()
    return time.perf_counter() - start, time.process_time() - cpu, read


def build_built_in() -> tuple[float, float, float]:
    """(wall s, CPU s, CPU s of loading the scenario) of one build."""
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    start, cpu = time.perf_counter(), time.process_time()
    scenario = load_scenario("lecture6_assignment1")
    read = time.process_time() - cpu
    FactoryRuntime(scenario).close()
    return time.perf_counter() - start, time.process_time() - cpu, read


def _cold(kind: str) -> tuple[float, float, float]:
    """One build of ``kind`` in a fresh process."""
    code = (
        "import json, logging, sys; sys.path.insert(0, 'bench'); import bench_launch as b; "
        "import omtp_drake.launch, omtp_drake.sim.runtime, omtp_drake.scenario; "
        "logging.getLogger('drake').setLevel(logging.ERROR); "
        f"print(json.dumps(b.build_{kind}()))"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    return tuple(json.loads(out.stdout.strip().splitlines()[-1]))  # type: ignore[return-value]


def _print(title: str, launch: list, built_in: list, loads: tuple[float, float]) -> None:
    def median(rows: list, k: int) -> float:
        return statistics.median(row[k] for row in rows)

    print(f"{title}: load average {loads[0]:.1f} before, {loads[1]:.1f} after (1 min)")
    print(
        f"  built-in scenario : CPU {median(built_in, 1):.3f} s "
        f"(loading the scenario {median(built_in, 2):.3f} s), wall {median(built_in, 0):.3f} s"
    )
    print(
        f"  course launch     : CPU {median(launch, 1):.3f} s (reading the files {median(launch, 2):.3f} s), "
        f"wall {median(launch, 0):.3f} s"
    )
    print(
        f"  ratio             : CPU {median(launch, 1) / median(built_in, 1):.2f}x, wall "
        f"{median(launch, 0) / median(built_in, 0):.2f}x (target <= 1.5x); "
        f"medians of {len(launch)}, interleaved"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cold", type=int, default=0, help="pairs of fresh processes (first builds)")
    args = parser.parse_args()
    import logging

    logging.getLogger("drake").setLevel(logging.ERROR)
    build_from_launch(), build_built_in()  # warm: imports, the mesh cache, the stand-ins
    load_before = os.getloadavg()[0]
    launch, built_in = [], []
    for _ in range(args.repeats):  # interleaved: the machine's load hits both alike
        launch.append(build_from_launch())
        built_in.append(build_built_in())
    _print("in one process (warm)", launch, built_in, (load_before, os.getloadavg()[0]))
    if args.cold:
        load_before = os.getloadavg()[0]
        cold_launch, cold_built_in = [], []
        for _ in range(args.cold):
            cold_launch.append(_cold("from_launch"))
            cold_built_in.append(_cold("built_in"))
        _print(
            "first build of a process (cold)", cold_launch, cold_built_in, (load_before, os.getloadavg()[0])
        )


if __name__ == "__main__":
    main()
