"""Cost of collision-aware motion planning (omtp_drake.control.motion) for robot 2 at bin 1.

Scene: scenario ``lecture6_assignment4`` (robot 2, a UR5, next to bin 1), no parts.
Goals: random tool poses around bin 1 (the tip within 0.35 m of the bin's axis
in x and y, 0.2-0.7 m above the floor: inside the bin (rim at 0.475), above it, or
beside it outside its walls; pointing down with a random yaw), turned into joint goals by ``ArmPlanner.ik`` (goals IK cannot reach
collision free are skipped). Each goal is planned twice: from R2Home, and from the
previous goal (a chain of moves in and out of the bin).

Printed: the build time of ``ArmPlanner``; per start mode the median and worst
planning time and the fraction of goals whose straight joint path was blocked
(those went through OMPL); IK and time-parameterization times. No pass/fail.

    OMTP_DRAKE_CACHE=/tmp/omtp_cache .venv/bin/python bench/bench_planning.py [--goals 20]
"""

import argparse
import logging
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from omtp_drake.cell import arms
from omtp_drake.control.motion import ArmPlanner
from omtp_drake.errors import PlanningError
from omtp_drake.scenario import load_scenario

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

BIN_CENTRE = np.array([-8.0, -2.2])


def random_goals(planner: ArmPlanner, count: int, rng: np.random.Generator) -> tuple[list, list]:
    """``count`` collision-free joint goals around bin 1, and the IK times (s)."""
    goals, ik_times = [], []
    seed = arms.named_pose("R2Place")
    while len(goals) < count:
        xy = BIN_CENTRE + rng.uniform(-0.35, 0.35, 2)
        z = rng.uniform(0.2, 0.7)
        X_WE = RigidTransform(RotationMatrix(RollPitchYaw(np.pi, 0.0, rng.uniform(-np.pi, np.pi))),
                              [xy[0], xy[1], z])
        start = time.perf_counter()
        try:
            goals.append(planner.ik(X_WE, q_seed=seed))
        except PlanningError:
            continue
        finally:
            ik_times.append(time.perf_counter() - start)
    return goals, ik_times


def summary(name: str, times: list[float], blocked: list[float], failed: int) -> None:
    print(f"{name:<22} median {statistics.median(times) * 1000:7.1f} ms   worst "
          f"{max(times) * 1000:7.1f} ms   straight path blocked {len(blocked)}/{len(times)}"
          f"   failed {failed}")
    if blocked:
        print(f"{'':<22} blocked only (OMPL): median {statistics.median(blocked) * 1000:7.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--goals", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=5.0)
    args = parser.parse_args()

    scenario = load_scenario("lecture6_assignment4")
    builds = []
    for _ in range(3):
        start = time.perf_counter()
        planner = ArmPlanner(scenario, "robot2")
        builds.append(time.perf_counter() - start)
    print(f"ArmPlanner build: median {statistics.median(builds) * 1000:.0f} ms "
          f"(first {builds[0] * 1000:.0f} ms), {len(builds)} builds")

    goals, ik_times = random_goals(planner, args.goals, np.random.default_rng(args.seed))
    print(f"IK (multi-seed, collision-checked): median {statistics.median(ik_times) * 1000:.1f} ms, "
          f"worst {max(ik_times) * 1000:.1f} ms, {len(goals)} goals of {len(ik_times)} poses")

    home = arms.named_pose("R2Home")
    paths = []
    for mode in ("from R2Home", "chained goal to goal"):
        times, blocked, failed = [], [], 0
        previous = home
        for goal in goals:
            start_q = home if mode == "from R2Home" else previous
            straight_free = not planner.path_collisions(start_q, goal)
            start = time.perf_counter()
            try:
                path = planner.plan(start_q, goal, timeout=args.timeout)
                paths.append(path)
            except PlanningError as error:
                failed += 1
                print(f"  failed: {error}")
            times.append(time.perf_counter() - start)
            if not straight_free:
                blocked.append(times[-1])
            previous = goal
        summary(mode, times, blocked, failed)

    planner.time_parameterize(paths[0])  # the first call imports toppra (scipy)
    retimes = []
    for path in paths:
        start = time.perf_counter()
        planner.time_parameterize(path)
        retimes.append(time.perf_counter() - start)
    print(f"time_parameterize: median {statistics.median(retimes) * 1000:.1f} ms, "
          f"worst {max(retimes) * 1000:.1f} ms over {len(paths)} paths")

    q = arms.named_pose("R2Place")
    X_WE = planner.forward_kinematics(q)
    line = [RigidTransform(X_WE.rotation(), X_WE.translation() + [0.0, 0.0, -0.3])]
    start = time.perf_counter()
    path, fraction = planner.cartesian_path(q, line)
    print(f"cartesian_path 0.3 m down at 5 mm steps: {(time.perf_counter() - start) * 1000:.0f} ms, "
          f"{len(path)} points, fraction {fraction:.2f}")


if __name__ == "__main__":
    main()
