"""Our Python at each of the driver's stops (issue 38): the world edits, the runtime's
tick callbacks and the event sources' bookkeeping, without the simulation between stops.

    python bench/bench_driver_stops.py [scenario] [--at 20 30 45] [--span 5] [--repeats 7]

Runs the scenario's task to each time ``--at``, then replaces the driver's Simulator by
one whose ``AdvanceTo`` only sets the time (a frozen world) and advances ``--span`` s:
the driver stops where it would, and every edit, callback and event source does its
work on the same state. Prints the stops and the CPU time (``thread_time``) per stop,
the least of ``--repeats`` runs from the same saved state: on a shared machine the least
is the cost of the work, the rest is other processes' load. Costs that a real stop shares
with the plant's next step (the geometry and kinematics caches an edit evaluates first)
are cached here, so this measures the Python and pybind calls themselves.
"""

from __future__ import annotations

import argparse
import logging
import time

from omtp_drake.tasks.run import TaskRun, prepare


class _FrozenSimulator:
    """A Simulator stand-in whose AdvanceTo only moves the time (counts the stops)."""

    def __init__(self, context):
        self.context = context
        self.stops = 0

    def AdvanceTo(self, t: float) -> None:
        self.context.SetTime(t)
        self.stops += 1


def per_stop(scenario: str, at: float, span: float, repeats: int) -> tuple[int, float]:
    """(stops in ``span`` s from ``at``, least CPU us per stop over ``repeats`` runs)."""
    with TaskRun(prepare(scenario)) as run:
        rt = run.runtime
        rt.advance_to(at)
        saved = rt.context.Clone()
        costs, stops = [], 0
        for _ in range(repeats):
            rt.context.SetTimeStateAndParametersFrom(saved)
            frozen = _FrozenSimulator(rt.context)
            rt.driver.simulator = frozen
            t0 = time.thread_time()
            rt.advance_to(at + span)
            costs.append((time.thread_time() - t0) / frozen.stops)
            stops = frozen.stops
    return stops, 1e6 * min(costs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="fill_bin")
    parser.add_argument("--at", type=float, nargs="+", default=[20.0, 30.0, 45.0])
    parser.add_argument("--span", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    for at in args.at:
        stops, us = per_stop(args.scenario, at, args.span, args.repeats)
        line = f"{args.scenario} from t = {at:g} s: {stops} stops in {args.span:g} s"
        print(f"{line}, {us:.1f} us of Python per stop")


if __name__ == "__main__":
    main()
