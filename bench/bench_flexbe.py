"""What the FlexBE engine costs: the Conveyor Pick behaviour of examples/flexbe under
``flexbe-run`` against the same pick as a plain rospy script under ``ros-run``
(``bench/flexbe_pick_ros.py``: the same services, topics, /compute_ik and /move_group
calls in the same order, polled at FlexBE's 10 Hz).

Printed per variant (interleaved repeats, best and median): wall time, process CPU time
(the machine may be shared: CPU time is what the run itself used), simulated time, parts
in bin 2; then the engine's overhead in percent of the ros-run time (best against best).
Target: <= 5 %. No pass/fail; numbers only.

    python bench/bench_flexbe.py [--parts 2] [--repeats 3]
"""

import argparse
import logging
import statistics
import time
from pathlib import Path

from omtp_drake.ros import run_script
from omtp_drake.ros.flexbe import run_behavior

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = "lecture7_flexbe"


def flexbe(parts: int) -> tuple[float, float, float, int, str]:
    wall, cpu = time.perf_counter(), time.process_time()
    report = run_behavior(
        "Conveyor Pick", [ROOT / "examples" / "flexbe"], scenario=SCENARIO, params={"parts": str(parts)}
    )
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return wall, cpu, report.sim_time_s, report.ledger["in_bin"]["bin_2"], str(report.outcome)


def ros(parts: int) -> tuple[float, float, float, int, str]:
    wall, cpu = time.perf_counter(), time.process_time()
    report = run_script(ROOT / "bench" / "flexbe_pick_ros.py", [str(parts)], scenario=SCENARIO)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return wall, cpu, report.sim_time_s, report.ledger["in_bin"]["bin_2"], f"exit {report.exit_code}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    flexbe(1)  # warm-up: meshes, imports, planner caches
    runs: dict[str, list] = {"flexbe-run": [], "ros-run": []}
    for _ in range(args.repeats):
        runs["flexbe-run"].append(flexbe(args.parts))
        runs["ros-run"].append(ros(args.parts))
    for name, rows in runs.items():
        walls, cpus = [r[0] for r in rows], [r[1] for r in rows]
        sims, bins, outcomes = {round(r[2], 2) for r in rows}, {r[3] for r in rows}, {r[4] for r in rows}
        print(
            f"{name:10s}: wall best {min(walls):.2f} s (median {statistics.median(walls):.2f}), "
            f"CPU best {min(cpus):.2f} s (median {statistics.median(cpus):.2f}); simulated {sorted(sims)} s; "
            f"bin 2: {sorted(bins)}; {sorted(outcomes)}"
        )
    f, r = runs["flexbe-run"], runs["ros-run"]
    for what, i in (("wall", 0), ("CPU", 1)):
        best_f, best_r = min(x[i] for x in f), min(x[i] for x in r)
        print(f"engine overhead ({what}, best against best): {100 * (best_f - best_r) / best_r:+.1f} %")


if __name__ == "__main__":
    main()
