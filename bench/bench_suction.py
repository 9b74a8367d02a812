"""Cost of the vacuum gripper, per backend.

Scene (tests/suction_rig.py, the rig the suction tests use): a world floor, 10 parts of 1 kg
(0.2 m cubes) on it, a tool on stiff SAP-PD joints carrying the course's vacuum
gripper, SAP point contact at the station's plant settings (10 ms steps). The tool presses
on one part, the gripper attaches it, and the tool then carries it back and
forth at 1 m/s (20 m/s^2 ramps) over the other parts for the rest of the run.
A driver loop advances in 50 ms ticks and calls ``sync_weld`` after each, as
the runtime does.

Printed per case: the real-time factor (simulated / wall time) of the whole
run, and the time of one evaluation of the force backend's ``spatial_forces``
output (what the plant pays every step), idle and holding. Fastest and median
of several runs; no pass/fail.

    python bench/bench_suction.py [--seconds 10]
"""

import argparse
import logging
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

from omtp_drake.scenario import SuctionConfig

# The suction rig lives with the tests that use it (tests/suction_rig.py).
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from suction_rig import PRESS, TOP, Rig, build_rig, plant_config, tool_q, trajectory  # noqa: E402

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

PARTS = [(0.0, 0.0, 0.0)] + [(0.5 * (k % 3) - 0.5, 0.5 + 0.5 * (k // 3), 0.3 * k) for k in range(9)]
RUNS = 5


def _motion(seconds: float):
    """Press, lift 0.3 m, then shuttle 1 m along x at 1 m/s until ``seconds``."""
    down = tool_q(0.0, 0.0, TOP - PRESS)
    up = down + [0, 0, 0.3, 0, 0]
    left, right = up + [-0.5, 0.8, 0, 0, 0], up + [0.5, 0.8, 0, 0, 0]
    waypoints = [(0.0, down), (0.2, down), (0.55, up), (1.55, left)]
    t, target = 1.55, right
    while t < seconds:
        t += 1.05
        waypoints.append((t, target))
        target = left if target is right else right
    return trajectory(waypoints, accel=20.0)


def _rtf(backend: str, seconds: float, enable: bool) -> tuple[float, Rig]:
    rig = build_rig(backend, _motion(seconds), parts=PARTS, mass=1.0,
                    config=SuctionConfig(backend=backend), log=False)
    rig.command(enable)
    start = time.perf_counter()
    rig.advance_to(seconds)
    wall = time.perf_counter() - start
    if enable and not rig.state().attached:
        raise RuntimeError(f"{backend}: the part was not held to the end")
    return seconds / wall, rig


def _time_us(fn: Callable[[], object], iterations: int = 2000) -> tuple[float, float]:
    for _ in range(100):
        fn()
    runs = []
    for _ in range(RUNS):
        start = time.perf_counter()
        for _ in range(iterations):
            fn()
        runs.append((time.perf_counter() - start) / iterations * 1e6)
    return min(runs), statistics.median(runs)


def _force_output_cost(rig: Rig) -> tuple[float, float]:
    """The output's calculation (the plant's poses and velocities already cached)."""
    port = rig.gripper.GetOutputPort("spatial_forces")
    context = rig.gripper.GetMyContextFromRoot(rig.context)
    value = port.Allocate()
    calc = rig.gripper._calc_forces  # what the framework calls on a cache miss
    return _time_us(lambda: calc(context, value))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0, help="simulated time per run")
    args = parser.parse_args()
    step_ms = 1e3 * plant_config().time_step
    print(f"scene: {len(PARTS)} parts of 1 kg, tool at 1 m/s, {step_ms:g} ms SAP point contact, "
          f"{args.seconds:g} s simulated per run, 50 ms ticks")
    print(f"{'case':<28} {'RTF best':>9} {'RTF median':>11}")
    rigs = {}
    for label, backend, enable in (("weld, off (nothing held)", "weld", False),
                                   ("force, off (nothing held)", "force", False),
                                   ("weld, holding", "weld", True),
                                   ("force, holding", "force", True)):
        rtfs = []
        for _ in range(3):
            rtf, rig = _rtf(backend, args.seconds, enable)
            rtfs.append(rtf)
        rigs[label] = rig
        print(f"{label:<28} {max(rtfs):9.2f} {statistics.median(rtfs):11.2f}")

    print()
    print("one calculation of spatial_forces [us] (paid every plant step by the force "
          "backend, plus the framework's call into Python):")
    held = rigs["force, holding"]
    best, median = _force_output_cost(held)
    print(f"  {'holding':<10} best {best:6.1f}  median {median:6.1f}")
    held.command(False)
    held.advance_to(held.time + 0.1)
    assert not held.state().attached
    best, median = _force_output_cost(held)
    print(f"  {'idle':<10} best {best:6.1f}  median {median:6.1f}")
    poses = held.plant.get_body_poses_output_port()
    velocities = held.plant.get_body_spatial_velocities_output_port()
    pc = held.plant_context
    best_p, _ = _time_us(lambda: poses.Eval(pc))
    best_v, _ = _time_us(lambda: velocities.Eval(pc))
    print(f"  of which pydrake's list conversion of body_poses {best_p:.1f} us and of "
          f"body_spatial_velocities {best_v:.1f} us ({held.plant.num_bodies()} bodies; "
          f"grows with the number of bodies)")


if __name__ == "__main__":
    main()
