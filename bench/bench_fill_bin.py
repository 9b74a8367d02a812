"""Benchmark of the fill-a-bin challenge over seeds.

    python bench/bench_fill_bin.py [--seeds 100] [--parts 10] [--budget 1200]

Runs ``fill_bin`` for seeds 0, 1, ... until ``--seeds`` runs or ``--budget``
wall seconds are used (the count run is printed), and prints a table: success
rate, mean and worst cycle time per pick (simulated), real-time factor and
wall time per fill. Numbers only; no pass/fail.
"""

from __future__ import annotations

import argparse
import logging
import statistics
import time

from omtp_drake.tasks.run import run_task


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=100)
    parser.add_argument("--parts", type=int, default=10)
    parser.add_argument("--budget", type=float, default=1200.0, help="wall seconds at most")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)

    start = time.perf_counter()
    rows = []
    print(f"{'seed':>5} {'ok':>3} {'in bin':>6} {'fails':>5} {'mean cyc':>8} {'max cyc':>8} "
          f"{'sim s':>7} {'wall s':>7} {'RTF':>5}")
    for seed in range(args.seeds):
        if time.perf_counter() - start > args.budget:
            break
        r = run_task("fill_bin", seed=seed, parts=args.parts)
        s = r.summary
        rows.append(r)
        print(f"{seed:5d} {'y' if r.success else 'n':>3} {s['in_bin']:6d} {s['failed']:5d} "
              f"{s['mean_cycle_time_s']:8.2f} {s['max_cycle_time_s']:8.2f} {s['sim_time_s']:7.1f} "
              f"{s['wall_time_s']:7.1f} {s['real_time_factor']:5.1f}", flush=True)
    cycles = [p.cycle_time for r in rows for p in r.picks if p.success]
    print(f"\nruns: {len(rows)} of {args.seeds} seeds ({args.parts} parts each) in "
          f"{time.perf_counter() - start:.0f} s wall")
    print(f"success rate: {sum(r.success for r in rows)}/{len(rows)} "
          f"({100 * sum(r.success for r in rows) / len(rows):.1f} %)")
    print(f"cycle time per pick (simulated): mean {statistics.mean(cycles):.2f} s, "
          f"worst {max(cycles):.2f} s over {len(cycles)} picks")
    print(f"failed attempts (recovered or not): {sum(r.summary['failed'] for r in rows)}")
    walls = [r.wall_time_s for r in rows]
    rtfs = [r.summary["real_time_factor"] for r in rows]
    print(f"wall time per fill: mean {statistics.mean(walls):.1f} s, worst {max(walls):.1f} s; "
          f"real-time factor mean {statistics.mean(rtfs):.1f}")


if __name__ == "__main__":
    main()
