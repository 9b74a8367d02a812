"""What each of our Python callbacks costs in a run (issue 20, bench/README.md item 9).

    python bench/callback_costs.py [fill_bin | lecture7_conveyor_pick | belt] [--seed 0]
        [--time-step 0.002] [--cpu] [--warm] [--by-mode]

Wraps each system callback and world edit of ``omtp_drake`` with ``perf_counter`` (no
profiler: a sampling profiler's own cost blurs calls of 10-200 us), runs the case once,
and prints for each: calls per simulated second, us per call, ms per simulated second.
A call costs several times what it costs timed alone, because the plant's step between
two calls leaves the CPU caches cold; this measures it where it happens.

Nested rows (marked ``in``) are also inside another row: the machine's step and the
camera images and the joint plans (DiffIK integrated ahead) inside the controller's
update. The total adds the top-level rows only. The wrappers add about 1 us a call.
``Driver._apply_due`` counts the driver's stops (one call each; its time includes the
edits and callbacks due there, so it is not added to the total).
"""

from __future__ import annotations

import argparse
import collections
import importlib
import time

#: (module, class, methods, nested): the callbacks to time.
CALLBACKS = [
    ("omtp_drake.control.pick_and_place.system", "PickAndPlaceController", ["_update"], False),
    ("omtp_drake.control.joint_plan", "PlanAhead", ["plan"], True),
    ("omtp_drake.control.pick_and_place.machine", "PickMachine", ["step"], True),
    ("omtp_drake.cell.suction", "SuctionGripper", ["_check", "_calc_state"], False),
    ("omtp_drake.cell.suction_holds", "ForceSuctionGripper", ["_calc_forces"], False),
    ("omtp_drake.cell.conveyor", "BreakBeam", ["_update"], False),
    ("omtp_drake.cell.conveyor", "ConveyorBelt", ["_calc_desired_state", "_check_beam"], False),
    ("omtp_drake.cell.logical_camera", "LogicalCamera", ["_update"], False),
    ("omtp_drake.cell.logical_camera", "LogicalCamera", ["_calc_image"], True),
    ("omtp_drake.cell.rest_clock", "RestClock", ["_update"], False),
    ("omtp_drake.sim.part_sleep", "PartSleep", ["__call__", "before_advance"], False),
    ("omtp_drake.sim.gripper_events", "GripperEvents", ["__call__", "before_advance", "next_time"], False),
    ("omtp_drake.sim.driver", "AutoSpawner", ["__call__", "next_time"], False),
    ("omtp_drake.tasks.run", "TaskRun", ["_write_off_lost_parts"], False),
    # One call per stop of the driver (its time includes the edits and callbacks due there).
    ("omtp_drake.sim.driver", "Driver", ["_apply_due"], True),
    ("omtp_drake.sim.driver", "DeletionWall", ["__call__"], False),
    ("omtp_drake.sim.driver", "BeltWrap", ["__call__"], False),
]


def instrument(clock=time.perf_counter) -> tuple[dict[str, float], collections.Counter, set[str]]:
    """Wraps the callbacks (before any system is built); returns the seconds (of
    ``clock``) and the calls per callback as they accumulate, and the nested ones' names."""
    seconds: dict[str, float] = collections.defaultdict(float)
    calls: collections.Counter = collections.Counter()
    nested: set[str] = set()
    for module, name, methods, inside in CALLBACKS:
        cls = getattr(importlib.import_module(module), name)
        for method in methods:
            function = cls.__dict__.get(method)
            if function is None:  # (an older checkout, compared with bench_versions-style runs)
                continue
            key = f"{name}.{method}"
            if inside:
                nested.add(key)

            def timed(*args, _function=function, _key=key, **kwargs):
                start = clock()
                try:
                    return _function(*args, **kwargs)
                finally:
                    seconds[_key] += clock() - start
                    calls[_key] += 1

            setattr(cls, method, timed)
    return seconds, calls, nested


def by_mode(clock=time.perf_counter) -> tuple[dict[str, float], collections.Counter]:
    """Wraps the pick-and-place controller's update (before any is built, over the
    wrapper :func:`instrument` put there) to count its time and calls by the mode it
    starts in: the updates that plan (WAIT_PART, ATTACH) apart from those while the arm
    travels (APPROACH, DESCEND, TRANSFER, HOME)."""
    from omtp_drake.control.pick_and_place.system import PickAndPlaceController

    seconds: dict[str, float] = collections.defaultdict(float)
    calls: collections.Counter = collections.Counter()
    update = PickAndPlaceController._update

    def timed(self, context, state):
        mode = self._control_state(context).mode.name
        start = clock()
        try:
            return update(self, context, state)
        finally:
            seconds[mode] += clock() - start
            calls[mode] += 1

    PickAndPlaceController._update = timed
    return seconds, calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "case", nargs="?", default="fill_bin", choices=["fill_bin", "lecture7_conveyor_pick", "belt"]
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--time-step", type=float, default=None, help="the plant's step (default: the scenario's)"
    )
    parser.add_argument(
        "--cpu",
        action="store_true",
        help="time each call by the thread's CPU time, not the wall clock (a busy machine)",
    )
    parser.add_argument(
        "--warm",
        action="store_true",
        help="run the case 8 simulated s first (the lazy imports, e.g. scipy in the first tool path, "
        "out of the figures: as `omtp-drake bench` times a run after recording one)",
    )
    parser.add_argument(
        "--by-mode",
        action="store_true",
        help="also the controller's update split by the mode it starts in",
    )
    args = parser.parse_args()
    clock = time.thread_time if args.cpu else time.perf_counter
    seconds, calls, nested = instrument(clock)
    modes, mode_calls = by_mode(clock) if args.by_mode else ({}, collections.Counter())
    from speed import belt_scenario  # bench/speed.py

    from omtp_drake.sim.runtime import FactoryRuntime
    from omtp_drake.tasks.run import prepare, run_task

    if args.warm and args.case != "belt":
        run_task(prepare(args.case, seed=args.seed), duration=8.0)
        for counts in (seconds, calls, modes, mode_calls):
            counts.clear()
    cpu0 = time.process_time()

    if args.case == "belt":  # as `omtp-drake bench` runs it: 10 parts riding, 10 s
        scenario = belt_scenario(10)
        if args.time_step is not None:
            scenario = scenario.with_time_step(args.time_step)
        runtime = FactoryRuntime(scenario)
        start = time.perf_counter()
        runtime.advance_to(10.0)
        simulated, wall = 10.0, time.perf_counter() - start
    else:
        scenario = prepare(args.case, seed=args.seed)
        if args.time_step is not None:
            scenario = scenario.with_time_step(args.time_step)
        result = run_task(scenario)
        simulated, wall = result.sim_time_s, result.wall_time_s
    per_second = 1e3 * wall / simulated
    step = "" if args.time_step is None else f" at a {1e3 * args.time_step:g} ms step"
    print(
        f"{args.case}{step}: {simulated:.1f} s simulated, run loop {per_second:.1f} ms per simulated s",
        end="",
    )
    print(
        f", process CPU {1e3 * (time.process_time() - cpu0) / simulated:.1f} ms per simulated s"
        " (with the wrappers)"
    )
    print("| callback | calls per simulated s | us per call | ms per simulated s |\n|---|---:|---:|---:|")
    for key in sorted(seconds, key=lambda k: -seconds[k]):
        label = f"{key} (in)" if key in nested else key
        print(
            f"| {label} | {calls[key] / simulated:.1f} | {1e6 * seconds[key] / calls[key]:.1f} | "
            f"{1e3 * seconds[key] / simulated:.2f} |"
        )
    total = sum(v for k, v in seconds.items() if k not in nested)
    print(f"| **all top-level callbacks** | | | **{1e3 * total / simulated:.2f}** |")
    if mode_calls:
        print("\n| the controller's update, by mode | calls per simulated s | us per call | ms per sim. s |")
        print("|---|---:|---:|---:|")
        for mode in sorted(modes, key=lambda m: -modes[m]):
            n, cpu = mode_calls[mode], modes[mode]
            print(f"| {mode} | {n / simulated:.2f} | {1e6 * cpu / n:.0f} | {1e3 * cpu / simulated:.2f} |")


if __name__ == "__main__":
    main()
