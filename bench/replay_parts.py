"""The replay *with the run's parts*: the bare plant replaying a run's arm motion and
carrying its parts as the run did (``speed.replay_seconds(..., parts=True)``).

The plain replay (``speed.replay_seconds``) has one part on the floor and no suction, so
the full run's ten parts (spawned, carried, stacked in the bin, asleep there) are physics
the replay does not pay. This one replays, at the times the run made them, every edit the
run made to the plant's and SceneGraph's state for its parts, and leaves the rest to the
physics:

- the pool's spawns and disposals (``PartStates.unpark`` at the spawn pose, ``park``);
- the weld suction's holds: the six distance constraints made at the part's current pose
  (``SuctionConstraints.attach``) when the run's constraints went on, released when off;
- the parts falling asleep and waking (``PartStates.sleep``/``wake``: joint locked,
  filters and corner spheres as in the run).

So the replay's plant carries the same free bodies, constraints, locks and collision
filters at the same times as the run's, and its parts move by the same physics under
the same arm motion: the same contact load. A kinematic replay of each part's recorded
pose was not used: a part whose pose is set every step is locked or overwritten, which
takes it out of (or fights) the contact solve it should load. The edits cost a few
Python stops (one per event, about 60 in ``fill_bin``), where the full run stops ~16
times a second.

Recording (:func:`watch_parts`) wraps the run's ``station.part_states`` edits (which
the pool and the sleep check call) and reads the weld constraints' held body after
every step (the monitor of ``speed.record_arm_motion``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Optional

from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context

from omtp_drake.cell.parts import PartStates
from omtp_drake.cell.suction_constraints import SuctionConstraints, declare_suction_constraints


@dataclass(frozen=True)
class PartEdit:
    """One edit the run made at time ``t``: ``kind`` is ``unpark`` (at ``X_WP``), ``park``,
    ``sleep`` (``X_WP``: where the run's part lay), ``wake``, ``attach`` (``robot``'s cup
    holds ``part``) or ``release`` (``robot``'s cup lets go)."""

    t: float
    kind: str
    part: str = ""
    X_WP: Optional[RigidTransform] = None
    robot: str = ""


def watch_parts(run) -> tuple[list[PartEdit], Callable[[Context], None]]:
    """Starts recording ``run``'s part edits: returns the list it fills and the function
    to call after every step (with the root Context) that notes the weld holds' changes."""
    station = run.runtime.station
    plant: MultibodyPlant = station.plant
    states = station.part_states
    edits: list[PartEdit] = []
    root = run.runtime.context
    plant_context = plant.GetMyContextFromRoot(root)
    parked, asleep = states.locked(plant_context)
    for name, instance in states.parts.items():  # in the world before the run starts
        if name not in parked:
            X_WP = plant.EvalBodyPoseInWorld(plant_context, plant.GetBodyByName(name, instance))
            edits.append(PartEdit(root.get_time(), "unpark", name, X_WP))
            if name in asleep:
                edits.append(PartEdit(root.get_time(), "sleep", name, X_WP))

    def wrap(kind: str, pose_arg: bool):
        inner = getattr(states, kind)

        def edit(root_context: Context, name: str, *args):
            X_WP = args[0] if pose_arg else None
            if kind == "sleep":
                body = plant.GetBodyByName(name, states.parts[name])
                X_WP = plant.EvalBodyPoseInWorld(plant.GetMyContextFromRoot(root_context), body)
            edits.append(PartEdit(root_context.get_time(), kind, name, X_WP))
            return inner(root_context, name, *args)

        setattr(states, kind, edit)  # this run's instance only

    for kind, pose_arg in (("unpark", True), ("park", False), ("sleep", False), ("wake", False)):
        wrap(kind, pose_arg)
    holds = {r: g.constraints for r, g in station.grippers.items() if hasattr(g, "constraints")}
    held: dict[str, str] = dict.fromkeys(holds, "")
    last = [0.0]

    def after_step(root_context: Context) -> None:
        # A hold changes between advances (sync_weld), at the end time of the step before.
        plant_context = plant.GetMyContextFromRoot(root_context)
        for robot, constraints in holds.items():
            index = constraints.held_body(plant, plant_context)
            part = plant.get_body(index).name() if index is not None else ""
            if part != held[robot]:
                kind = "attach" if part else "release"
                edits.append(PartEdit(last[0], kind, part or held[robot], robot=robot))
                held[robot] = part
        last[0] = root_context.get_time()

    return edits, after_step


def declare_holds(plant: MultibodyPlant, models) -> dict[str, SuctionConstraints]:
    """The weld grippers' constraints, declared before ``Finalize`` as the station does."""
    if not models.parts:
        return {}
    first = next(iter(models.parts))
    placeholder = plant.GetBodyByName(first, models.parts[first])
    return {
        name: declare_suction_constraints(
            plant, plant.GetBodyByName(f"{handles.config.gripper}_cup", handles.gripper), placeholder
        )
        for name, handles in models.arms.items()
        if handles.gripper is not None
    }


def advance_with_parts(
    simulator: Simulator, models, holds: dict[str, SuctionConstraints], edits: list[PartEdit], end: float
) -> dict[str, float]:
    """Advances ``simulator`` (a bare plant from ``speed.bare_simulator(..., holds=...)``)
    to ``end``, making ``edits`` at their times. Returns, per part that fell asleep, how
    far (m) the replayed part lay from where the run's part fell asleep (the last time)."""
    diagram = simulator.get_system()
    plant = next(s for s in diagram.GetSystems() if isinstance(s, MultibodyPlant))
    scene_graph = next(s for s in diagram.GetSystems() if type(s).__name__.startswith("SceneGraph"))
    states = PartStates(plant, scene_graph, models.parts)
    context = simulator.get_mutable_context()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    apart: dict[str, float] = {}
    for edit in edits:
        if edit.t > context.get_time():
            simulator.AdvanceTo(min(edit.t, end))
        if edit.t > end:
            break
        if edit.kind == "unpark":
            states.unpark(context, edit.part, edit.X_WP)
        elif edit.kind == "park":
            states.park(context, edit.part)
        elif edit.kind == "sleep":
            body = plant.GetBodyByName(edit.part, models.parts[edit.part])
            X_WP = plant.EvalBodyPoseInWorld(plant_context, body)
            apart[edit.part] = float(((X_WP.translation() - edit.X_WP.translation()) ** 2).sum() ** 0.5)
            states.sleep(context, edit.part)
        elif edit.kind == "wake":
            states.wake(context, edit.part)
        elif edit.kind == "attach":
            body = plant.GetBodyByName(edit.part, models.parts[edit.part])
            holds[edit.robot].attach(plant, plant_context, body)
        else:
            holds[edit.robot].release(plant, plant_context)
    if context.get_time() < end:
        simulator.AdvanceTo(end)
    return apart


def main() -> None:
    """``python bench/replay_parts.py [--rounds 3] [--profile-replay out.raw]``: fill_bin's
    full run against its replay and its replay with the parts, interleaved, CPU ms per
    simulated s (this process) and the load; with ``--profile-replay``, py-spy (--native)
    attaches to this process and samples the plain replays only (read with
    ``profile_split.py --replay``)."""
    import argparse
    import os
    import time

    from omtp_drake.bench_command import speed_module
    from omtp_drake.tasks.run import prepare, run_task

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--profile-replay", help="py-spy raw samples of the plain replays, here")
    parser.add_argument("--with-parts", action="store_true", help="profile the replays with the parts")
    args = parser.parse_args()
    speed = speed_module()
    fill = prepare("fill_bin")
    floor = speed.with_parts(fill, [[-8.3, -1.23, 0.051]], fill.pool_part_size)
    motion, _ = speed.record_arm_motion(fill)
    print(f"recorded: {motion.duration:.1f} s, {len(motion.parts)} part edits", flush=True)
    holds: dict = {}
    simulator, models = speed.bare_simulator(fill, motion, holds)
    apart = advance_with_parts(simulator, models, holds, list(motion.parts), motion.duration)
    print(
        f"replayed parts at their sleep: at most {1e3 * max(apart.values()):.4f} mm from the run's",
        flush=True,
    )
    if args.profile_replay:
        if args.with_parts:
            _profile_replays(
                args.profile_replay, args.rounds, lambda: speed.replay_seconds(fill, motion, True)[0]
            )
        else:
            _profile_replays(args.profile_replay, args.rounds, lambda: speed.replay_seconds(floor, motion)[0])
        return

    def full_run() -> float:
        cpu = time.process_time()
        result = run_task(fill)
        return (time.process_time() - cpu) / result.sim_time_s

    cases = {
        "full": full_run,
        "replay": lambda: speed.replay_seconds(floor, motion)[0],
        "parts": lambda: speed.replay_seconds(fill, motion, parts=True)[0],
    }
    for k in range(args.rounds):
        load = os.getloadavg()[0]
        order = list(cases)[k % 3 :] + list(cases)[: k % 3]  # the order rotates
        cpus = {name: cases[name]() for name in order}
        full, replay, carried = cpus["full"], cpus["replay"], cpus["parts"]
        print(
            f"round {k + 1}: full {1e3 * full:6.1f}  replay {1e3 * replay:6.1f}"
            f"  with parts {1e3 * carried:6.1f} ms/s;  {full / replay:.2f}x, {full / carried:.2f}x"
            f"  load {load:.1f}-{os.getloadavg()[0]:.1f}",
            flush=True,
        )


def _profile_replays(raw: str, rounds: int, replay: Callable[[], float]) -> None:
    """py-spy (--native, 100 Hz) attached to this process while it runs ``replay`` ``rounds`` times."""
    import os
    import shutil
    import signal
    import subprocess
    import time

    command = [shutil.which("py-spy") or "py-spy", "record", "--native", "-r", "100", "-f", "raw", "-o", raw]
    child = subprocess.Popen([*command, "-p", str(os.getpid())], stderr=subprocess.DEVNULL)
    time.sleep(2.0)
    for _ in range(rounds):
        print(f"replay {1e3 * replay():6.1f} ms/s  load {os.getloadavg()[0]:.1f}", flush=True)
    child.send_signal(signal.SIGINT)
    child.wait()


if __name__ == "__main__":
    main()
