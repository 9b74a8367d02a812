"""Benchmark of the factory diagram: build time and real-time factor.

Both arms move between their named poses (Home, PreGrasp, Place, Home) with
both logical cameras on, at 2, 4, 5 and 10 ms plant steps (10 ms is the default). Prints numbers
only.

    python bench/bench_factory.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import logging
import statistics
import time

from omtp_drake.cell.station import build_station
from omtp_drake.demos import named_pose_tour
from omtp_drake.scenario import load_scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)

    build_station(load_scenario("omtp_factory"))  # warm the model cache and imports
    builds = []
    for _ in range(args.repeats):
        t = time.perf_counter()
        build_station(load_scenario("omtp_factory"))
        builds.append(time.perf_counter() - t)
    print(f"diagram build time: median {statistics.median(builds):.3f} s "
          f"(min {min(builds):.3f}, max {max(builds):.3f}, n={args.repeats})")

    print(f"{'step':>8} {'cameras':>8} {'sim s':>8} {'wall s':>8} {'RTF':>7}")
    for step in (0.002, 0.004, 0.005, 0.01):
        for cameras in (True, False):
            scenario = load_scenario("omtp_factory")
            scenario.plant_config.time_step = step
            if not cameras:
                scenario.cameras = []
            runs = [named_pose_tour(scenario) for _ in range(args.repeats)]
            best = max(runs, key=lambda r: r.real_time_factor)
            print(f"{step * 1e3:6.0f}ms {str(cameras):>8} {best.sim_time_s:8.2f} "
                  f"{best.wall_time_s:8.2f} {best.real_time_factor:7.1f}")


if __name__ == "__main__":
    main()
