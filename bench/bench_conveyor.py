"""Benchmark of the conveyor cell: lecture7_conveyor with 10 parts on the belt.

    python bench/bench_conveyor.py [--seconds 10] [--profile]

Ten parts ride the running belt (break-beam stop off so they keep moving;
the deletion wall recycles them), both arms hold, both cameras on. Prints the
real-time factor for each suction backend, and with --profile the top of a
cProfile of the Python side.
"""

from __future__ import annotations

import argparse
import cProfile
import logging
import pstats
import time
from dataclasses import replace

from omtp_drake.scenario import load_scenario
from omtp_drake.sim.runtime import FactoryRuntime

REST_Z = 0.92 + 0.1 + 0.001


def build(backend: str) -> FactoryRuntime:
    scenario = load_scenario("lecture7_conveyor")
    scenario = replace(scenario, spawner=None, part_pool=12,
                       conveyor=replace(scenario.conveyor, stop_on_beam=False),
                       suction=replace(scenario.suction, backend=backend))
    rt = FactoryRuntime(scenario)
    for k in range(10):
        rt.spawn_part(xyz=[1.2, 4.5 - 0.5 * k, REST_Z])
    return rt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    for backend in ("weld", "force"):
        best = 0.0
        for _ in range(args.repeats):
            rt = build(backend)
            t = time.perf_counter()
            rt.advance_to(args.seconds)
            best = max(best, args.seconds / (time.perf_counter() - t))
        ledger = rt.ledger()
        print(f"{backend:>6}: real-time factor {best:.1f} over {args.seconds:.0f} s "
              f"(on belt {ledger.on_belt}, disposed {ledger.disposed})")
    if args.profile:
        rt = build("weld")
        profile = cProfile.Profile()
        profile.enable()
        rt.advance_to(args.seconds)
        profile.disable()
        pstats.Stats(profile).sort_stats("tottime").print_stats(8)


if __name__ == "__main__":
    main()
