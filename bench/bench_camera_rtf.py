"""Real-time factor of the factory with and without the logical cameras.

The ``omtp_factory`` scenario with 20 parts placed in the cameras' views (10 on
the belt under camera 1, 10 on the floor under camera 2), both arms holding
their Home pose, 2 ms plant steps, 10 s simulated. Cases: both cameras on at
10 Hz, and cameras removed (``scenario.cameras = []``). Prints the best of
``--repeats`` runs of each, and the change of the real-time factor (target:
the cameras cost at most 5 %). Prints numbers only; no pass/fail.

    python bench/bench_camera_rtf.py [--repeats 3] [--sim-time 10] [--profile]

Both the wall-clock real-time factor and the CPU-time one (``process_time``:
less sensitive to other load on the machine) are printed.

``--unsampled`` sets the plant's ``use_sampled_output_ports`` to false (see the
report in the docstring of ``main``). ``--profile`` runs the camera case once
more under cProfile and prints the functions with the most own time.
"""

from __future__ import annotations

import argparse
import cProfile
import logging
import pstats
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from pydrake.systems.analysis import Simulator  # noqa: E402

from omtp_drake.cell.station import build_station  # noqa: E402
from omtp_drake.scenario import PartConfig, Scenario, load_scenario  # noqa: E402

STEP = 0.002


def scenario_with_parts(cameras: bool, sampled: bool = True) -> Scenario:
    """omtp_factory + 20 resting parts in the cameras' views; optionally no cameras."""
    scenario = load_scenario("omtp_factory")
    scenario.plant_config.time_step = STEP
    scenario.plant_config.use_sampled_output_ports = sampled
    k = 0
    offsets = (-0.48, -0.24, 0.0, 0.24, 0.48)
    # Camera 1 looks down at (1.2, 1.8) from z = 2.0: the belt (top 0.92) under it.
    for x in (1.05, 1.35):
        for dy in offsets:
            k += 1
            scenario.parts.append(PartConfig(name=f"object_{k}", xyz=[x, 1.8 + dy, 1.021]))
    # Camera 2 looks down at (-8.3, -1.23) from z = 1.8: the floor under it.
    for x in (-8.42, -8.18):
        for dy in offsets:
            k += 1
            scenario.parts.append(PartConfig(name=f"object_{k}", xyz=[x, -1.23 + dy, 0.101]))
    if not cameras:
        scenario.cameras = []
    return scenario


def run(cameras: bool, sim_time: float, sampled: bool = True) -> tuple[float, float, int]:
    """(wall time, CPU time of the simulation, models seen at the end)."""
    station = build_station(scenario_with_parts(cameras, sampled))
    context = station.create_context()  # arms held at Home
    simulator = Simulator(station.diagram, context)
    simulator.Initialize()
    start, start_cpu = time.perf_counter(), time.process_time()
    simulator.AdvanceTo(sim_time)
    wall, cpu = time.perf_counter() - start, time.process_time() - start_cpu
    seen = sum(len(station.diagram.GetOutputPort(f"{c}.image").Eval(context).models)
               for c in station.cameras)
    return wall, cpu, seen


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--sim-time", type=float, default=10.0)
    parser.add_argument("--unsampled", action="store_true",
                        help="plant_config.use_sampled_output_ports = false")
    parser.add_argument("--profile", action="store_true", help="also profile the camera case")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    sampled = not args.unsampled

    run(True, 0.1, sampled)  # warm caches and imports
    print(f"step {STEP * 1e3:.0f} ms, {args.sim_time:g} s simulated, best of {args.repeats}, "
          f"use_sampled_output_ports={sampled}")
    print(f"{'cameras':>8} {'seen':>5} {'wall s':>8} {'RTF':>7} {'cpu s':>8} {'RTF(cpu)':>9}")
    rtf: dict[bool, tuple[float, float]] = {}
    for cameras in (True, False):
        runs = [run(cameras, args.sim_time, sampled) for _ in range(args.repeats)]
        wall = min(r[0] for r in runs)
        cpu = min(r[1] for r in runs)
        seen = runs[-1][2]
        rtf[cameras] = (args.sim_time / wall, args.sim_time / cpu)
        print(f"{'on' if cameras else 'off':>8} {seen:>5} {wall:8.3f} {rtf[cameras][0]:7.2f} "
              f"{cpu:8.3f} {rtf[cameras][1]:9.2f}")
    for label, k in (("wall", 0), ("cpu", 1)):
        change = (rtf[False][k] - rtf[True][k]) / rtf[False][k] * 100
        print(f"cameras cost {change:.1f} % of the real-time factor ({label}; target <= 5 %)")

    if args.profile:
        profile = cProfile.Profile()
        profile.enable()
        run(True, args.sim_time, sampled)
        profile.disable()
        pstats.Stats(profile).sort_stats("tottime").print_stats(20)


if __name__ == "__main__":
    main()
