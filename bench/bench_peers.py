"""Our ``fill_bin`` against the same job in PyBullet and in MuJoCo, and how cost grows with parts.

    python bench/bench_peers.py [--repeats 3] [--growth-seconds 4] [--no-growth] [--no-job]

The job (bench/peer_job.py): one run of our ``fill_bin`` is recorded (robot 2's joint
commands as its servo sampled them, the suction command, when and where each part
appeared); PyBullet (bench/peer_pybullet.py, its 240 Hz default, ravens-style suction: a
fixed constraint created at touch) and MuJoCo (bench/peer_mujoco.py, its defaults: 2 ms,
Euler; a weld equality switched on at touch; position actuators) replay it with the same
arm, gripper, pedestal, bin and parts, and count the parts that end in the bin. Then, in
rounds (each runs ours, PyBullet and MuJoCo once, so a busy minute touches all alike):
our ``run_task("fill_bin")`` at its defaults and both replays, in CPU seconds of this
process per simulated second (the medians are printed, with the load average).

Cost growth: CPU per simulated second with 1, 10, 30 and 100 parts (0.05 m cubes,
0.2 kg) resting in bin 1, for our cell (sleeping on and off), PyBullet (its default, and
with Bullet's sleeping enabled on the parts) and MuJoCo (its default, and with its
sleeping flag); and in our cell riding the belt (sleeping on and off). The arms hold
still; each case settles for 1 s (untimed: our parts fall asleep after 0.5 s at rest),
then runs ``--growth-seconds``.
"""

from __future__ import annotations

import argparse
import logging
import os
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import peer_mujoco
import peer_pybullet
from peer_job import FillBinJob, bin_slots, record_fill_bin

#: The growth rows' part counts and part edge (m): 100 such parts fit in bin 1 (49 a layer).
GROWTH_COUNTS = (1, 10, 30, 100)
GROWTH_SIZE = 0.05
#: Issue 46's targets: ours over PyBullet and over MuJoCo, each at its defaults.
TARGETS = {"PyBullet": 1.3, "MuJoCo": 1.5}


@dataclass(frozen=True)
class PeerRun:
    """One engine's job: CPU seconds per simulated second (median of the rounds), parts
    it left in the bin (each round), the build's CPU seconds."""

    engine: str
    cpu: float
    in_bin: tuple[int, ...]
    build: float


def ours_cpu() -> tuple[float, int]:
    """CPU seconds per simulated second of ``run_task("fill_bin")`` at its defaults (build
    excluded, as in the peers), and the parts it put in the bin."""
    from omtp_drake.tasks.run import TaskRun, prepare, run_task

    scenario = prepare("fill_bin")
    marks: dict[str, float] = {}

    def start(_run: TaskRun) -> None:
        marks["start"] = time.process_time()

    result = run_task(scenario, on_start=start)
    cpu = (time.process_time() - marks["start"]) / result.sim_time_s
    return cpu, result.ledger.in_bin.get(result.bin, 0)


def compare(job: FillBinJob, repeats: int, say: Callable[[str], None], ours: bool = True) -> list[PeerRun]:
    """Ours (unless not ``ours``), PyBullet and MuJoCo on ``job``, ``repeats`` interleaved rounds."""
    engines: dict[str, Callable[[], tuple[float, int, float]]] = {
        "PyBullet": lambda: peer_pybullet.run_fill_bin(job),
        "MuJoCo": lambda: peer_mujoco.run_fill_bin(job),
    }
    if ours:
        engines = {"ours (fill_bin)": lambda: (*ours_cpu(), float("nan")), **engines}
    runs: dict[str, list[tuple[float, int, float]]] = {name: [] for name in engines}
    for round_ in range(repeats):
        for name, run in engines.items():
            say(f"{name} (round {round_ + 1} of {repeats})")
            runs[name].append(run())
    return [
        PeerRun(
            name,
            statistics.median(r[0] for r in rs),
            tuple(int(r[1]) for r in rs),
            statistics.median(r[2] for r in rs),
        )
        for name, rs in runs.items()
    ]


def peer_timings(repeats: int) -> tuple[tuple[str, float, float], ...]:
    """``omtp-drake bench``'s peer rows: (engine, CPU seconds per simulated second on a
    freshly recorded fill_bin job, the median of ``repeats``, target for ours over it)."""
    runs = compare(record_fill_bin(), repeats, lambda text: None, ours=False)
    return tuple((r.engine, r.cpu, TARGETS[r.engine]) for r in runs)


def compare_table(runs: Sequence[PeerRun], job: FillBinJob) -> str:
    ours = runs[0]
    lines = [
        f"fill_bin job: {len(job.spawns)} parts, {job.duration:.1f} s simulated (our recorded run put "
        f"{job.in_bin} in the bin)",
        f"{'engine':<18} {'CPU ms/sim s':>12} {'in bin':>10} {'ours / this':>12}  target",
    ]
    for r in runs:
        ratio = ours.cpu / r.cpu
        target = TARGETS.get(r.engine)
        mark = "" if target is None else f"<= {target}x {'met' if ratio <= target else 'NOT met'}"
        bins = "/".join(str(n) for n in r.in_bin)
        lines.append(f"{r.engine:<18} {1e3 * r.cpu:12.1f} {bins:>10} {ratio:11.2f}x  {mark}")
    return "\n".join(lines)


def ours_resting_cpu(count: int, belt: bool, sleep: bool, seconds: float) -> tuple[float, int]:
    """Our cell (``fill_bin``'s, no task) with ``count`` parts resting in bin 1 or riding
    the belt (``lecture7_conveyor``'s, at full power, the beam's stop off): CPU seconds
    per simulated second over ``seconds`` after 1 s of settling, and how many parts are
    in bin 1 at the end (on the belt: how many are still in the world)."""
    from omtp_drake.cell.conveyor import BeltGeometry
    from omtp_drake.scenario import PartConfig, load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    if belt:
        scenario = load_scenario("lecture7_conveyor")
        assert scenario.conveyor is not None
        scenario = replace(scenario, conveyor=replace(scenario.conveyor, stop_on_beam=False, power=100.0))
        g = BeltGeometry.from_model()
        xyzs = [
            (g.x - 0.15 + 0.1 * (k % 4), 4.8 - 0.1 * (k // 4), g.top + GROWTH_SIZE / 2 + 0.001)
            for k in range(count)
        ]
    else:
        scenario = load_scenario("fill_bin")
        xyzs = bin_slots(count, GROWTH_SIZE, [tuple(scenario.bins[0].xyz)])
    parts = [
        PartConfig(name=f"bench_{k}", xyz=list(p), size=GROWTH_SIZE, mass=0.2) for k, p in enumerate(xyzs)
    ]
    scenario = replace(
        scenario,
        parts=parts,
        spawner=None,
        task=None,
        part_pool=0,
        sleep=replace(scenario.sleep, enabled=sleep),
    )
    rt = FactoryRuntime(scenario)
    try:
        rt.advance_to(1.0)
        cpu = time.process_time()
        rt.advance_to(1.0 + seconds)
        cpu = (time.process_time() - cpu) / seconds
        return cpu, (len(rt.parts_in_world()) if belt else rt.ledger().in_bin.get("bin_1", 0))
    finally:
        rt.close()


def growth(job: FillBinJob, seconds: float, say: Callable[[str], None]) -> dict[str, list[tuple[float, int]]]:
    """The growth table's rows: name -> (CPU seconds per simulated second, parts still in
    the bin or on the belt at the end) per count."""
    slots = {n: bin_slots(n, GROWTH_SIZE, [job.bin_xyz]) for n in GROWTH_COUNTS}
    cases: dict[str, Callable[[int], tuple[float, int]]] = {
        "ours, in bin 1, sleeping on": lambda n: ours_resting_cpu(n, False, True, seconds),
        "ours, in bin 1, sleeping off": lambda n: ours_resting_cpu(n, False, False, seconds),
        "ours, riding the belt, sleeping on": lambda n: ours_resting_cpu(n, True, True, seconds),
        "ours, riding the belt, sleeping off": lambda n: ours_resting_cpu(n, True, False, seconds),
        "PyBullet, in bin 1 (default)": lambda n: peer_pybullet.resting_cpu(job, slots[n], seconds),
        "PyBullet, in bin 1, sleeping on": lambda n: peer_pybullet.resting_cpu(job, slots[n], seconds, True),
        "MuJoCo, in bin 1 (default)": lambda n: peer_mujoco.resting_cpu(job, slots[n], seconds),
        "MuJoCo, in bin 1, sleeping on": lambda n: peer_mujoco.resting_cpu(job, slots[n], seconds, True),
    }
    ours_resting_cpu(1, False, True, 0.5)  # warm up (the first cell in a process costs more)
    rows: dict[str, list[tuple[float, int]]] = {}
    for name, case in cases.items():
        say(f"growth: {name}")
        rows[name] = [case(n) for n in GROWTH_COUNTS]
    return rows


def growth_table(rows: dict[str, list[tuple[float, int]]]) -> str:
    """The rows as text; a cell whose parts did not all stay (in the bin, or in the world
    on the belt) says how many did."""
    width = max(len(name) for name in rows)
    head = f"{'CPU ms per simulated s':<{width}} " + " ".join(f"{n:>6} parts" for n in GROWTH_COUNTS)
    lines = [head]
    for name, values in rows.items():
        cells = [
            f"{1e3 * cpu:.1f}" + ("" if kept == n else f" ({kept} kept)")
            for (cpu, kept), n in zip(values, GROWTH_COUNTS)
        ]
        lines.append(f"{name:<{width}} " + " ".join(f"{c:>12}" for c in cells))
    return "\n".join(lines)


def load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.1f} {five:.1f} {fifteen:.1f} on {os.cpu_count()} CPUs"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--growth-seconds", type=float, default=4.0)
    parser.add_argument("--no-growth", action="store_true", help="skip the cost-growth table")
    parser.add_argument("--no-job", action="store_true", help="skip the fill_bin comparison")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.WARNING)

    def say(text: str) -> None:
        print(f"measuring {text} ... ({load()})", flush=True)

    say("our fill_bin, recorded for the peers")
    job = record_fill_bin()
    if not args.no_job:
        print(f"(before: {load()})")
        runs = compare(job, args.repeats, say)
        print(compare_table(runs, job))
        print(f"(medians of {args.repeats} interleaved rounds, CPU time of this process; after: {load()})")
    if not args.no_growth:
        print(growth_table(growth(job, args.growth_seconds, say)))
        print(f"(one run per cell, {args.growth_seconds:g} s each after 1 s settling; {load()})")


if __name__ == "__main__":
    main()
