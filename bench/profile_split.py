"""Where a run's time goes: splits a native py-spy profile into the simulation's parts.

Record a profile (py-spy samples Drake's C++ with --native), then split it:

    py-spy record --native -r 250 -f raw -o fill_bin.raw -- \\
        python -c "from omtp_drake.tasks.run import run_task; run_task('fill_bin')"
    python bench/profile_split.py fill_bin.raw

Only samples inside ``run_task`` (the simulation, not imports or the build) count.
Each sample goes to the first category, in the order below, one of its frames matches.
"""

from __future__ import annotations

import argparse
import collections
import re

#: (category, what it is, frame patterns), in priority order.
CATEGORIES = [
    ("contact solve", "SAP's solve of the discrete contact problem",
     ["SapSolver<double>::SolveWithGuess"]),
    ("geometry queries", "SceneGraph: point-pair penetration, pose updates",
     ["ComputePointPairPenetration", "SceneGraph<double>::CalcPoseUpdate", "GeometryState<double>::"]),
    ("arm servos", "inverse dynamics of the two arms' servos, command sampling",
     ["InverseDynamics<double>", "InverseDynamicsController", "MatrixGain", "LinearSystem",
      "AffineSystem", "Demultiplexer", "Multiplexer"]),
    ("contact problem", "building SAP's problem: free motion, contact pairs and Jacobians, constraints",
     ["SapDriver<double>::CalcContactProblemCache", "CalcDiscreteContactPairs",
      "CalcAccelerationsDueToNonConstraintForcesCache"]),
    ("DiffIK", "Drake's DifferentialInverseKinematicsIntegrator (QP every 10 ms)",
     ["DifferentialInverseKinematics"]),
    ("plant step, other", "the rest of MultibodyPlant's discrete step",
     ["MultibodyPlant<double>::CalcStepDiscrete", "DiscreteUpdateManager"]),
    ("our Python", "omtp_drake's systems, driver and task loop (Python frames, no Drake below)",
     []),
    ("simulator overhead", "the Simulator, events, caching, the rest of the diagram",
     ["Simulator<double>::"]),
]


def split(path: str) -> tuple[int, collections.Counter]:
    totals: collections.Counter = collections.Counter()
    samples = 0
    for line in open(path):
        stack, _, count = line.rstrip().rpartition(" ")
        frames = stack.split(";")
        if not any("run_task" in f for f in frames):
            continue
        n = int(count)
        samples += n
        totals[_category(frames)] += n
    return samples, totals


def _category(frames: list[str]) -> str:
    for name, _, patterns in CATEGORIES:
        if name == "our Python":
            ours = [i for i, f in enumerate(frames) if "omtp_drake/" in f]
            if ours and not any("drake::" in f for f in frames[ours[-1]:]) and \
                    not re.search(r"advance_to|run_task", frames[ours[-1]]):
                return name
            continue
        if any(p in f for f in frames for p in patterns):
            return name
    return "other (the task loop)"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("profile", help="a py-spy --native -f raw file")
    args = parser.parse_args()
    samples, totals = split(args.profile)
    print("| part | share | what |\n|---|---:|---|")
    for name, what, _ in CATEGORIES + [("other (the task loop)", "run_task's own loop", [])]:
        print(f"| {name} | {100 * totals[name] / samples:.1f} % | {what} |")
    print(f"\n({samples} samples inside run_task)")


if __name__ == "__main__":
    main()
