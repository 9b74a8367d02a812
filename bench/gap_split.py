"""Where fill_bin's time goes beyond the bare plant: the full run and its replay, side by side.

    python bench/gap_split.py [--repeats 2] [--profile out.raw]

In one process: records ``fill_bin``'s arm motion (``speed.record_arm_motion``), then
``repeats`` times runs the task (*full*) and the bare plant replaying that motion (*replay*,
``speed.bare_simulator``: the same plant, servos and parked pool, one part on the floor, none
of our systems), as ``speed.replay_timing`` does. Prints, for each, CPU ms per simulated s,
the simulator's counts (steps, discrete and unrestricted updates) and the load average.

With ``--profile``, py-spy (``--native``) attaches to this process after the recording and
samples the timed runs; the samples are then split by *where they sit in the simulation*
(the callback or event handler they are under), full against replay: the gap's rows are
what the full run adds. Run under ``OMTP_DRAKE_HEAP=glibc`` (py-spy's native unwinding loses
a process on the tuned heap, see ``profile_split.profile_parts``).
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import speed  # noqa: E402

from omtp_drake.tasks.run import prepare, run_task  # noqa: E402


def _under(*names: str):
    return lambda frames: any(n in f for f in frames for n in names)


def _all(*tests):
    return lambda frames: all(t(frames) for t in tests)


_ADVANCE = "drake::systems::Simulator::AdvanceTo"

#: (row, test on a sample's cleaned frames), the first that holds takes the sample.
ROWS = [
    ("controller: DiffIK integrated ahead (DiffIkAhead.knots)", _under("DiffIkAhead")),
    ("controller: rest of its update (machine, travel checks, FK)", _under("PickAndPlaceController._update")),
    (
        "suction check (SuctionGripper's update)",
        _all(_under("SuctionGripper"), _under("HandleUnrestrictedUpdate")),
    ),
    ("other unrestricted updates (cameras, state clones, dispatch)", _under("HandleUnrestrictedUpdate")),
    ("driver stop: sleep check (PartSleep)", _all(_under("Driver._apply_due"), _under("PartSleep"))),
    ("driver stop: spawner, grippers' events, run's ticks, wall", _under("Driver._apply_due")),
    ("driver: Python between AdvanceTo calls", lambda fr: "Driver.advance_to" in fr and _ADVANCE not in fr),
    ("plant step (MultibodyPlant::CalcStepDiscrete)", _under("CalcStepDiscrete")),
    ("other discrete updates (samplers, jerk stream, beam)", _under("CalcDiscreteVariableUpdate")),
    ("applying discrete updates", _under("DoApplyDiscreteVariableUpdate")),
    ("time advance, witness bookkeeping (IntegrateContinuousState)", _under("IntegrateContinuousState")),
    ("simulator: next update time, event collections", lambda fr: _ADVANCE in fr),
    ("other", lambda fr: True),
]


def _clean(frame: str) -> str:
    found = re.match(r"\s*(.*?) \(", frame)
    name = found.group(1) if found else frame
    for _ in range(3):
        name = re.sub(r"<[^<>]*>", "", name)
    return name


def split(path: str) -> dict[str, collections.Counter]:
    """Samples per row of :data:`ROWS`, for the full runs and the replays."""
    counts = {"full": collections.Counter(), "replay": collections.Counter()}
    for line in open(path):
        stack, _, n = line.rstrip().rpartition(" ")
        frames = [_clean(f) for f in stack.split(";")]
        if "run_task" in frames and "Driver.advance_to" in frames:
            phase = "full"
        elif _ADVANCE in frames and "run_task" not in frames and "_replay" in frames:
            phase = "replay"
        else:
            continue
        row = next(name for name, test in ROWS if test(frames))
        counts[phase][row] += int(n)
    return counts


def table(counts: dict[str, collections.Counter]) -> str:
    full, replay = sum(counts["full"].values()), sum(counts["replay"].values())
    gap = full - replay
    lines = [
        f"(samples: full {full}, replay {replay}, full / replay {full / max(replay, 1):.2f}x)",
        "| where | full | replay | gap | share of the gap |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, _ in ROWS:
        f, r = counts["full"][name], counts["replay"][name]
        if f or r:
            lines.append(f"| {name} | {f} | {r} | {f - r} | {100 * (f - r) / max(gap, 1):.1f} % |")
    return "\n".join(lines)


def _stats(simulator) -> dict[str, int]:
    return {
        "steps": simulator.get_num_steps_taken(),
        "discrete": simulator.get_num_discrete_updates(),
        "unrestricted": simulator.get_num_unrestricted_updates(),
    }


def _replay(scenario, motion) -> tuple[float, dict[str, int]]:
    simulator, _models = speed.bare_simulator(scenario, motion)
    cpu = time.process_time()
    simulator.AdvanceTo(motion.duration)
    return (time.process_time() - cpu) / motion.duration, _stats(simulator)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--profile", help="write py-spy's raw samples here and print the split")
    args = parser.parse_args()
    fill = prepare("fill_bin")
    floor = speed.with_parts(fill, [[-8.3, -1.23, 0.051]], fill.pool_part_size)
    motion, _ = speed.record_arm_motion(fill)
    spy = None
    if args.profile:
        command = [shutil.which("py-spy") or "py-spy", "record", "--native", "-r", "100", "-f", "raw"]
        spy = subprocess.Popen(
            [*command, "-o", args.profile, "-p", str(os.getpid())], stderr=subprocess.DEVNULL
        )
        time.sleep(2.0)
    simulators: list = []
    for _ in range(args.repeats):
        cpu = time.process_time()
        result = run_task(fill, on_start=lambda run: simulators.append(run.runtime.simulator))
        full = (time.process_time() - cpu) / result.sim_time_s
        print(
            f"full   {1e3 * full:6.1f} ms/s  {_stats(simulators[-1])}  load {os.getloadavg()[0]:.1f}",
            flush=True,
        )
        replay, stats = _replay(floor, motion)
        print(
            f"replay {1e3 * replay:6.1f} ms/s  {stats} load {os.getloadavg()[0]:.1f} ({full / replay:.2f}x)",
            flush=True,
        )
    if spy is not None:
        spy.send_signal(2)  # SIGINT: py-spy writes what it sampled
        spy.wait()
        print(table(split(args.profile)))


if __name__ == "__main__":
    main()
