"""Variants of one scenario's task run, timed in turn (h-speed3, 2026-11-29): a change
of *when* our Python runs gives another run (not the same floats), so the variants are
not compared bit for bit as ``paired_chunks.py`` does; only their CPU is.

    python bench/paired_variants.py [scenario] --variants base,sleep10 [--rounds 3]
    python bench/paired_variants.py [scenario] --variants base,sleep10 --processes --pairs 3

In-process (the default): each round builds every variant in one fresh process and
advances them ``--chunk`` simulated seconds in turn (the order rotating from chunk to
chunk: the second of a pair runs on caches the first warmed), timing each chunk's thread
CPU, so all see the same load within a second; it prints each variant's total CPU per
simulated second and its ratio to the first variant's. The machine's load swings whole
runs by 10-25 % (bench/README.md), which this pairing cancels; run an A/A (``base,same``)
beside a comparison to see what is left.

``--processes``: each pair runs every variant once in a fresh process each (the order
alternating), the child's user+sys CPU of ``run_task`` after a warm-up run of 8 s, as
``speed.replay_timing`` measures.

A variant (:data:`VARIANTS`) changes the scenario, or the code while the run is built.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import replace

from omtp_drake.scenario import Scenario


def _sleep_rate(hz: float) -> Callable[[Scenario], Scenario]:
    def change(scenario: Scenario) -> Scenario:
        return replace(scenario, sleep=replace(scenario.sleep, check_rate_hz=hz))

    return change


@contextlib.contextmanager
def _substeps(n: int) -> Iterator[None]:
    """``n`` DiffIK steps per 50 ms knot for what is built inside (``SUBSTEPS`` is
    ``PlanAhead``'s default argument)."""
    from omtp_drake.control import joint_plan

    before = joint_plan.PlanAhead.__init__.__defaults__
    joint_plan.PlanAhead.__init__.__defaults__ = (n,)
    try:
        yield
    finally:
        joint_plan.PlanAhead.__init__.__defaults__ = before


@contextlib.contextmanager
def _task_tick(period: float) -> Iterator[None]:
    """The task run's ticks (``TaskRun``'s ``on_tick`` callbacks) every ``period`` s."""
    from omtp_drake.sim.runtime import FactoryRuntime

    before = FactoryRuntime.on_tick
    FactoryRuntime.on_tick = lambda self, cb: self.driver.every(period, lambda: cb(self))  # type: ignore[method-assign]
    try:
        yield
    finally:
        FactoryRuntime.on_tick = before  # type: ignore[method-assign]


@contextlib.contextmanager
def _both(a: contextlib.AbstractContextManager, b: contextlib.AbstractContextManager) -> Iterator[None]:
    with a, b:
        yield


@contextlib.contextmanager
def _nothing() -> Iterator[None]:
    yield


_Code = Callable[[], contextlib.AbstractContextManager]
#: name -> (what it changes in the scenario, what it changes in the code while building).
VARIANTS: dict[str, tuple[Callable[[Scenario], Scenario], _Code]] = {
    "base": (lambda s: s, _nothing),
    "same": (lambda s: s, _nothing),  # an A/A pair: the noise floor
    "sleep10": (_sleep_rate(10.0), _nothing),
    "sleep20": (_sleep_rate(20.0), _nothing),
    "substeps1": (lambda s: s, lambda: _substeps(1)),
    "substeps2": (lambda s: s, lambda: _substeps(2)),
    "sleep10ticks10": (_sleep_rate(10.0), lambda: _task_tick(0.1)),
    "all": (_sleep_rate(10.0), lambda: _both(_task_tick(0.1), _substeps(1))),
}


def build(scenario_name: str, variant: str):
    from omtp_drake.tasks.run import TaskRun, prepare

    change, code = VARIANTS[variant]
    with code():
        return TaskRun(change(prepare(scenario_name)))


def in_process(scenario_name: str, names: list[str], chunk: float, until: float) -> dict[str, float]:
    """Thread CPU (ms) per simulated second of each variant, advanced in turn."""
    runs = {name: build(scenario_name, name) for name in names}
    cpu = dict.fromkeys(names, 0.0)
    t, k = 0.0, 0
    while t < until - 1e-9:
        t, k = min(t + chunk, until), k + 1
        order = names[k % len(names) :] + names[: k % len(names)]
        for name in order:
            start = time.thread_time()
            runs[name].runtime.advance_to(t)
            cpu[name] += time.thread_time() - start
    for name, run in runs.items():
        picks = [p for p in run.history().picks if p.success]
        print(f"  {name}: placed {len(picks)}, steps {run.runtime.simulator.get_num_steps_taken()}")
    return {name: 1e3 * c / t for name, c in cpu.items()}


def child(scenario_name: str, variant: str) -> None:
    """One warm task run of ``variant`` in this process; its figures as JSON."""
    from omtp_drake.tasks.run import prepare, run_task

    change, code = VARIANTS[variant]
    scenario = change(prepare(scenario_name))
    with code():
        run_task(scenario, duration=8.0)  # warm-up: the lazy imports
        cpu = time.process_time()
        result = run_task(scenario)
        cpu = time.process_time() - cpu
    summary = result.summary
    print(
        json.dumps(
            {
                "cpu_ms_per_s": 1e3 * cpu / result.sim_time_s,
                "sim_s": result.sim_time_s,
                "placed": summary["succeeded"],
                "mean_cycle": summary["mean_cycle_time_s"],
            }
        )
    )


def _report(names: list[str], rows: dict[str, list[float]]) -> None:
    first = names[0]
    for name in names[1:]:
        ratios = [r / b for r, b in zip(rows[name], rows[first])]
        print(
            f"{name} / {first}: median {statistics.median(ratios):.3f}, "
            f"spread {min(ratios):.3f}-{max(ratios):.3f} ({len(ratios)} pairs); "
            f"medians {statistics.median(rows[name]):.1f} / {statistics.median(rows[first]):.1f}"
            " ms per simulated s"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", nargs="?", default="fill_bin")
    parser.add_argument("--variants", default="base,same")
    parser.add_argument("--rounds", type=int, default=3, help="in-process rounds (a process each)")
    parser.add_argument("--chunk", type=float, default=1.0)
    parser.add_argument("--until", type=float, default=60.0)
    parser.add_argument("--processes", action="store_true", help="whole runs, a process each")
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--round", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    names = args.variants.split(",")
    if args.child:
        child(args.scenario, args.child)
        return
    if args.round:
        print(json.dumps(in_process(args.scenario, names, args.chunk, args.until)))
        return
    rows: dict[str, list[float]] = {n: [] for n in names}
    me = [sys.executable, __file__, args.scenario]
    if args.processes:
        for k in range(args.pairs):
            for name in names if k % 2 == 0 else names[::-1]:
                out = subprocess.run([*me, "--child", name], capture_output=True, text=True, check=True)
                row = json.loads(out.stdout.strip().splitlines()[-1])
                rows[name].append(row["cpu_ms_per_s"])
                print(f"pair {k + 1} {name}: {row}  load {os.getloadavg()[0]:.1f}", flush=True)
    else:
        for k in range(args.rounds):
            load = os.getloadavg()[0]
            rotated = names[k % len(names) :] + names[: k % len(names)]  # who is built first
            out = subprocess.run(
                [*me, "--round", "--variants", ",".join(rotated), "--chunk", str(args.chunk)]
                + ["--until", str(args.until)],
                capture_output=True,
                text=True,
                check=True,
            )
            lines = out.stdout.strip().splitlines()
            result = json.loads(lines[-1])
            for name in names:
                rows[name].append(result[name])
            print(
                f"round {k + 1} (load {load:.1f} -> {os.getloadavg()[0]:.1f}): "
                + ", ".join(f"{n} {result[n]:.1f}" for n in names),
                *lines[:-1],
                sep="\n",
                flush=True,
            )
    _report(names, rows)


if __name__ == "__main__":
    main()
