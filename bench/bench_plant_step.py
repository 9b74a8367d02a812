"""The plant step study of issue 46: each task scenario, the vacuum failing mid-transfer and the belt
at the break beam, run at plant steps of 10, 16 and 20 ms; prints the outcome rows (parts placed and
failed, the ledger's bins and floor, mean cycle time) and the CPU seconds per simulated second.

    python bench/bench_plant_step.py [--steps 0.01,0.016,0.02] [--seeds 2] [--failure-seeds 4]

A step is supported where every row equals the 10 ms row and the cycle times agree within 2 %.
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_soak import vacuum_failure_mid_transfer  # noqa: E402

from omtp_drake import FactoryRuntime  # noqa: E402
from omtp_drake.scenario import load_scenario  # noqa: E402
from omtp_drake.tasks.run import run_task  # noqa: E402

TASKS = ("fill_bin", "lecture6_assignment4", "lecture7_conveyor_pick", "lecture7_flexbe")


def task_row(result, cpu: float) -> str:
    s, ledger = result.to_dict()["summary"], result.ledger
    return (
        f"placed {s['succeeded']:2d} failed {s['failed']} bins {dict(ledger.in_bin)} floor {ledger.on_floor} "
        f"cycle {s['mean_cycle_time_s']:.2f} s  cpu/sim {1000 * cpu / s['sim_time_s']:.0f} ms"
    )


def beam_row(step: float) -> str:
    runtime = FactoryRuntime(load_scenario("lecture7_conveyor").with_time_step(step))
    try:
        runtime.advance_to(6.0)
        parts = runtime.ledger().to_dict()["parts"]
        return f"beam {runtime.break_beam()} belt power {runtime.conveyor_power()} ledger {parts}"
    finally:
        runtime.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", default="0.01,0.016,0.02")
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--failure-seeds", type=int, default=4)
    args = parser.parse_args()
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    for step in (float(s) for s in args.steps.split(",")):
        print(f"== plant step {1000 * step:g} ms", flush=True)
        print(f"  lecture7_conveyor at 6 s: {beam_row(step)}", flush=True)
        for name in TASKS:
            for seed in range(args.seeds):
                scenario = dataclasses.replace(load_scenario(name).with_time_step(step), seed=seed)
                t0 = time.process_time()
                result = run_task(scenario)
                print(f"  {name} seed {seed}: {task_row(result, time.process_time() - t0)}", flush=True)
        for seed in range(args.failure_seeds):
            scenario = dataclasses.replace(load_scenario("fill_bin").with_time_step(step), seed=seed)
            t0 = time.process_time()
            result = vacuum_failure_mid_transfer(scenario, None)
            print(f"  vacuum failure seed {seed}: {task_row(result, time.process_time() - t0)}", flush=True)


if __name__ == "__main__":
    main()
