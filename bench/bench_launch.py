"""Building the cell from a student's files (the course-layout launch of tests/fixtures)
against building it from the built-in scenario: wall time of each, interleaved, and the
ratio (target <= 2x). Each build is the scenario (read from the launch, or loaded) plus
the runtime the commands build on it (station, diagram, context).

    python bench/bench_launch.py [--repeats 5]
"""

import argparse
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WORKSPACE = ROOT / "tests" / "fixtures" / "catkin_ws" / "src"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


def build_from_launch() -> tuple[float, float]:
    from omtp_drake.launch import own_cell
    from omtp_drake.sim.runtime import FactoryRuntime

    start = time.perf_counter()
    scenario = own_cell(LAUNCH, workspace=[WORKSPACE]).scenario
    read = time.perf_counter() - start
    FactoryRuntime(scenario)
    return time.perf_counter() - start, read


def build_built_in() -> tuple[float, float]:
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    start = time.perf_counter()
    scenario = load_scenario("lecture6_assignment1")
    read = time.perf_counter() - start
    FactoryRuntime(scenario)
    return time.perf_counter() - start, read


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    import logging

    logging.getLogger("drake").setLevel(logging.ERROR)
    build_from_launch(), build_built_in()  # warm: imports, the mesh cache, the stand-ins
    launch, built_in = [], []
    for _ in range(args.repeats):  # interleaved: the machine's load hits both alike
        launch.append(build_from_launch())
        built_in.append(build_built_in())
    t_launch = statistics.median(t for t, _ in launch)
    t_built = statistics.median(t for t, _ in built_in)
    print(f"built-in scenario : {t_built:.3f} s (of which loading the scenario {statistics.median(r for _, r in built_in):.3f} s)")
    print(f"course launch     : {t_launch:.3f} s (of which reading the files {statistics.median(r for _, r in launch):.3f} s)")
    print(f"ratio             : {t_launch / t_built:.2f}x (target <= 2x); median of {args.repeats}, interleaved")


if __name__ == "__main__":
    main()
