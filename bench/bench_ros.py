"""What ros-run costs: the assignment-4 ROS example against the same logic on ``Cell``.

1. ``examples/ros/lecture6_assignment4.py`` (PARTS parts) through ``run_script``, against
   :func:`cell_logic`: the same moves, waits and services written on the ``Cell`` API
   (R2Home, spawn, wait 1.5 s, camera 2 + tf, above the part, vacuum on, the cup pressed
   onto the part, wait 0.3 s, R2Home, R2Place, vacuum off, wait 0.5 s, R2Home). Printed:
   wall time of each (best of the repeats, interleaved), the simulated time they covered,
   the parts they put in bin 1 and the overhead of ros-run in percent. Target: <= 10 %.

``grade``'s throughput (a class of copies on W workers) is ``bench_grade.py``'s.

No pass/fail; numbers only.

    python bench/bench_ros.py [--parts 1] [--repeats 3]
"""

import argparse
import logging
import time
from pathlib import Path

import numpy as np

from omtp_drake import Cell
from omtp_drake.ros import run_script

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "ros"
SCENARIO = "lecture6_assignment4"


def tool_down_pose(cell: Cell, arm, p_W: np.ndarray, height: float):
    """The suction_cup pose ``height`` above ``p_W``, the tool as at R2Home (straight down)."""
    from pydrake.math import RigidTransform

    return RigidTransform(arm.tool_pose("suction_cup").rotation(), p_W + [0.0, 0.0, height])


def cell_logic(parts: int) -> tuple[float, float, int]:
    """The example's logic on Cell: (wall s, simulated s, parts in bin 1)."""
    start = time.perf_counter()
    with Cell(SCENARIO, auto_spawn=False) as cell:
        arm, vacuum, camera = cell.arm("robot2"), cell.gripper("robot2"), cell.camera("logical_camera_2")
        arm.go("R2Home")
        for _ in range(parts):
            part = cell.spawn_part()
            cell.wait(1.5)
            p = cell.tf.transform_pose(camera.image().pose_of(part), "world").pose.translation()
            arm.go(tool_down_pose(cell, arm, p, 0.35), frame="suction_cup")
            vacuum.on()
            arm.go(tool_down_pose(cell, arm, p, 0.16), frame="suction_cup")
            cell.wait(0.3)
            arm.go("R2Home")
            arm.go("R2Place")
            vacuum.off()
            cell.wait(0.5)
            arm.go("R2Home")
        return time.perf_counter() - start, cell.time, cell.ledger().in_bin["bin_1"]


def ros_logic(parts: int) -> tuple[float, float, int]:
    start = time.perf_counter()
    # settle_after=0: the same simulated span as the Cell run (which does not run on after its end).
    report = run_script(EXAMPLES / "lecture6_assignment4.py", [str(parts)], scenario=SCENARIO, settle_after=0)
    if report.exception:
        raise RuntimeError(report.exception)
    return time.perf_counter() - start, report.sim_time_s, report.in_bins


def bench_overhead(parts: int, repeats: int) -> None:
    rows: dict[str, list[tuple[float, float, int]]] = {"Cell": [], "ros-run": []}
    for _ in range(repeats):
        rows["Cell"].append(cell_logic(parts))
        rows["ros-run"].append(ros_logic(parts))
    best = {k: min(v) for k, v in rows.items()}
    for name, (wall, sim, in_bin) in best.items():
        print(f"{name:8s} wall {wall:6.2f} s (best of {repeats})  simulated {sim:6.2f} s  in bin_1: {in_bin}")
    overhead = 100 * (best["ros-run"][0] / best["Cell"][0] - 1)
    print(f"ros-run overhead over Cell: {overhead:+.1f} % (target <= 10 %)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    bench_overhead(args.parts, args.repeats)


if __name__ == "__main__":
    main()
