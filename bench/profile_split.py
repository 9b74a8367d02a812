"""Where a run's time goes: splits a native py-spy profile into the simulation's parts.

Record a profile (py-spy samples Drake's C++ with --native; attach it to the running
process with ``-p``: a child py-spy starts itself loses most samples here, see
``profile_parts``), then split it:

    OMTP_DRAKE_HEAP=glibc python -c "from omtp_drake.tasks.run import run_task; \\
        run_task('fill_bin')" & sleep 2
    py-spy record --native -r 100 -f raw -o fill_bin.raw -p $!
    python bench/profile_split.py fill_bin.raw [--modules]

(``--modules``: "our Python" by omtp_drake module, the innermost of ours in each sample.)

(``profile_parts`` does both, for ``omtp-drake bench``'s profile rows.)

The shares are of the samples inside the run: the driver's ``advance_to`` (the
simulation). The rest of ``run_task`` (building the diagram, the result) is printed
apart, as the build. Each sample of the run goes to the first category, in the
order below, one of its frames matches.
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

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
    ("DiffIK", "Drake's differential IK: its QPs, integrated ahead along each decided path",
     ["DifferentialInverseKinematics"]),
    ("plant step, other", "the rest of MultibodyPlant's discrete step",
     ["MultibodyPlant<double>::CalcStepDiscrete", "DiscreteUpdateManager"]),
    ("our Python", "omtp_drake's systems, driver and task loop (Python frames, no Drake below)",
     []),
    ("simulator overhead", "the Simulator, events, caching, the rest of the diagram",
     ["Simulator<double>::"]),
]


#: Seconds after the child starts before py-spy attaches (Python and its imports are up;
#: the run's build may still be going, and is split apart from the run).
ATTACH_AFTER_S = 2.0

#: A frame of the run: the driver advancing the simulation.
RUN_FRAME = re.compile(r"advance_to \(.*omtp_drake/sim/driver\.py")
#: A frame of the bare plant's replay (bench/speed.py), and its simulation inside it.
REPLAY_FRAME = re.compile(r"replay_seconds \(.*speed\.py")
ADVANCE_FRAME = "Simulator<double>::AdvanceTo"


def split(path: str, replay: bool = False) -> tuple[int, collections.Counter, int]:
    """The samples inside the run, their count per category, and the samples of
    ``run_task`` outside the run (the build). With ``replay``: the samples inside the bare
    plant's replay (``speed.replay_seconds``'s ``AdvanceTo``) instead, and its build."""
    totals: collections.Counter = collections.Counter()
    samples = build = 0
    outer, inner = (REPLAY_FRAME, ADVANCE_FRAME) if replay else (None, None)
    for line in open(path):
        stack, _, count = line.rstrip().rpartition(" ")
        frames = stack.split(";")
        if outer is not None:
            if not any(outer.search(f) for f in frames):
                continue
            inside = any(inner in f for f in frames)
        elif not any("run_task" in f for f in frames):
            continue
        else:
            inside = any(RUN_FRAME.search(f) for f in frames)
        n = int(count)
        if not inside:
            build += n
            continue
        samples += n
        totals[_category(frames)] += n
    return samples, totals, build


#: What no category matches.
OTHER = ("other (the task loop)", "run_task's own loop, the driver's stops, pybind11", [])


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


def profile_parts(scenario: str = "fill_bin", rate: int = 100) -> tuple[tuple[tuple[str, float], ...], str]:
    """``scenario``'s task run in a child under ``py-spy record --native`` and split into
    the parts of bench/profile_split.py: ((part, share of the run's samples), ...), and a
    note (why there is no profile, or how many samples it has)."""
    spy = shutil.which("py-spy") or str(Path(sys.executable).with_name("py-spy"))
    if not Path(spy).is_file():
        return (), "(no profile rows: py-spy is not installed; pip install py-spy)"
    with tempfile.TemporaryDirectory() as folder:
        raw = Path(folder) / "profile.raw"
        code = f"from omtp_drake.tasks.run import run_task; run_task({scenario!r})"
        # py-spy's native sampling loses a process whose heap omtp_drake.sim.heap tuned (a
        # fill_bin run: 1 sample, 747 errors; 1,615 samples with glibc's heap), so the child
        # keeps glibc's heap: the shares are of that heap's run (its page faults show as
        # kernel time inside the functions that touch fresh pages).
        env = {**os.environ, "OMTP_DRAKE_HEAP": "glibc"}
        # py-spy attaches to the running child (``-p``) rather than starting it: a child
        # that py-spy starts itself lost almost every sample on this machine ("Failed to
        # copy PyThreadState head pointer": 6 samples and 8,428 errors in a fill_bin run),
        # one it attaches to after Python started is sampled whole (27,363 samples, 4 errors).
        child = subprocess.Popen([sys.executable, "-c", code], env=env)
        try:
            time.sleep(ATTACH_AFTER_S)  # the run's build and imports take longer
            command = [spy, "record", "--native", "-r", str(rate), "-f", "raw", "-o", str(raw)]
            done = subprocess.run([*command, "-p", str(child.pid)], capture_output=True, text=True)
        finally:
            child.wait()
        if done.returncode != 0 or not raw.is_file():
            return (), f"(no profile rows: py-spy failed: {done.stderr.strip().splitlines()[-1:]})"
        samples, totals, build = split(str(raw))
    if not samples:
        return (), "(no profile rows: py-spy recorded no sample inside the run)"
    names = [name for name, _, _ in CATEGORIES] + [OTHER[0]]
    note = (
        f"(profile: {samples} samples of {scenario}'s run at {rate} Hz, {build} more in its build; "
        "glibc's heap, see profile_parts)"
    )
    return tuple((name, totals[name] / samples) for name in names), note


#: "simulator overhead" split further (``--overhead``): (part, frame patterns), the first
#: any frame of a sample matches takes it.
OVERHEAD_PARTS = [
    ("invalidation (DependencyTracker, NotifySubscribers)",
     ["DependencyTracker", "NotifySubscribers", "NotePrerequisiteChange"]),
    ("event collections (Clear, AddToEnd, ...)", ["EventCollection"]),
    ("next update time", ["CalcNextUpdateTime", "DoCalcNextUpdateTime"]),
    ("heap (malloc, free, new, delete)", ["malloc", "_int_free", "cfree", "operator new", "operator delete"]),
    ("caches, contexts, ports", ["Cache", "Context", "Port"]),
    ("the rest", [""]),
]


def overhead_parts(path: str, replay: bool = False) -> collections.Counter:
    """The "simulator overhead" samples per :data:`OVERHEAD_PARTS`."""
    parts: collections.Counter = collections.Counter()
    for line in open(path):
        stack, _, count = line.rstrip().rpartition(" ")
        frames = stack.split(";")
        inside = (
            any(REPLAY_FRAME.search(f) for f in frames) and any(ADVANCE_FRAME in f for f in frames)
            if replay
            else any(RUN_FRAME.search(f) for f in frames)
        )
        if inside and _category(frames) == "simulator overhead":
            part = next(n for n, ps in OVERHEAD_PARTS if any(p in f for f in frames for p in ps))
            parts[part] += int(count)
    return parts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("profile", help="a py-spy --native -f raw file")
    parser.add_argument("--modules", action="store_true", help="our Python by omtp_drake module")
    parser.add_argument(
        "--replay", action="store_true", help="split the bare plant's replay (bench/replay_parts.py) instead"
    )
    parser.add_argument("--overhead", action="store_true", help="the simulator overhead split further")
    args = parser.parse_args()
    samples, totals, build = split(args.profile, args.replay)
    print("| part | share | what |\n|---|---:|---|")
    for name, what, _ in CATEGORIES + [OTHER]:
        print(f"| {name} | {100 * totals[name] / samples:.1f} % | {what} |")
    where = "the replay's AdvanceTo" if args.replay else "the run"
    print(f"\n({samples} samples inside {where}; the build and the rest: {build} more)")
    if args.overhead:
        print("\n| simulator overhead: part | share of the run |\n|---|---:|")
        parts = overhead_parts(args.profile, args.replay)
        for name, _ in OVERHEAD_PARTS:
            print(f"| {name} | {100 * parts[name] / samples:.1f} % |")
    if args.modules:
        print("\n| our Python: module | share of the run |\n|---|---:|")
        for module, n in ours_by_module(args.profile).most_common():
            print(f"| {module} | {100 * n / samples:.1f} % |")


def ours_by_module(path: str) -> collections.Counter:
    """The run's "our Python" samples per omtp_drake module (the innermost frame of ours)."""
    modules: collections.Counter = collections.Counter()
    for line in open(path):
        stack, _, count = line.rstrip().rpartition(" ")
        frames = stack.split(";")
        if any(RUN_FRAME.search(f) for f in frames) and _category(frames) == "our Python":
            leaf = [f for f in frames if "omtp_drake/" in f][-1]
            found = re.search(r"omtp_drake/([\w/]+)\.py", leaf)
            modules[found.group(1).replace("/", ".") if found else leaf] += int(count)
    return modules


if __name__ == "__main__":
    main()
