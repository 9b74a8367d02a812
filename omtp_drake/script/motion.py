"""An arm's moves in the running cell: a :class:`Plan` handed to the arm's
commander and stepped to its end, with its guard and contact checks
(:class:`MoveRunner`), and what the move did (:class:`MoveResult`).

A move that touches anything it should not stops the arm and raises
:class:`~omtp_drake.errors.CollisionError` naming what it hit; a guard
(``until``) that holds stops the arm within :data:`STOP_TIME`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any, Optional

import numpy as np
from pydrake.systems.framework import Context
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.errors import CollisionError
from omtp_drake.script.arm_commander import ArmCommander, JointCommand
from omtp_drake.script.scene import CellPlanningScene
from omtp_drake.sim.runtime import FactoryRuntime

#: How often (s) a guarded move checks its condition, and an unguarded one its contacts.
GUARD_PERIOD = 0.01
CONTACT_CHECK_PERIOD = 0.05
#: A joint move has arrived when every joint is this close (rad) to its goal.
SETTLE_TOLERANCE = 5e-4
#: ...and waits at most this long (s) after its trajectory's end for that.
SETTLE_TIMEOUT = 1.0
#: A guarded move that fires comes to rest over this time (s), decelerating evenly.
STOP_TIME = 0.1


@dataclass(frozen=True)
class Plan:
    """A timed joint motion of one arm, ready to :meth:`Arm.execute <omtp_drake.script.arm.Arm.execute>`.

    Attributes:
        trajectory: joint positions over the plan's own time (from 0).
        path: the joint waypoints it was timed through.
        kind: ``joint`` (straight or planned around obstacles), ``cartesian``.
        fraction: for a Cartesian plan, the fraction of the asked motion it covers.
    """

    trajectory: PiecewisePolynomial
    path: tuple[np.ndarray, ...]
    kind: str
    fraction: float = 1.0

    @property
    def duration(self) -> float:
        return self.trajectory.end_time() - self.trajectory.start_time()

    def __iter__(self) -> Iterator[Any]:
        """``plan, fraction = arm.compute_cartesian_path(...)`` unpacks like MoveIt's tuple."""
        return iter((self, self.fraction))


@dataclass(frozen=True)
class MoveResult:
    """What a move did.

    Attributes:
        start, end: simulated times (s).
        stopped: a guard (``until``) stopped the move before its end.
        q: the arm's joint positions when the call returned.
    """

    start: float
    end: float
    stopped: bool
    q: np.ndarray = field(repr=False)


class MoveRunner:
    """An arm's motions in the running cell: a plan handed to its commander, run
    with its guard and contact checks, and stopped when the guard fires."""

    def __init__(
        self,
        runtime: FactoryRuntime,
        name: str,
        commander: ArmCommander,
        scene: CellPlanningScene,
        step_hooks: list[Callable[[], None]],
    ):
        self._runtime = runtime
        self._commander = commander
        self._scene = scene
        self._step_hooks = step_hooks
        self.name = name

    def _joint_values(self) -> np.ndarray:
        return self._runtime.joint_positions(self.name)

    def contacts(self) -> list[tuple[str, str]]:
        """What the arm or its gripper touches now, as sorted (own body, other body)
        name pairs: the static cell, the other arm, and parts added to the planning
        scene. Other parts are left out: they are pressed and pushed by physics (the
        cup's vacuum attaches one on contact). The motion commands stop with
        ``CollisionError`` when this is not empty."""
        plant = self._runtime.station.plant
        plant_context = plant.GetMyContextFromRoot(self._runtime.context)
        # SceneGraph's penetration query: the pairs the plant's contact results would
        # list, at a fifth of the cost of evaluating those after a step.
        query = plant.get_geometry_query_input_port().Eval(plant_context)
        pairs = query.ComputePointPairPenetration()
        if not pairs:
            return []
        inspector = query.inspector()
        own, parts = self._contact_bodies
        names = self._scene.names()  # parts in it are obstacles, but for the one held
        held = self._held_part() if names else ""
        guarded = {parts[n] for n in names if n in parts and n != held}
        ignored = set(parts.values()) - guarded
        touched = set()
        for pair in pairs:
            a, b = (plant.GetBodyFromFrameId(inspector.GetFrameId(g)) for g in (pair.id_A, pair.id_B))
            for mine, other in ((a, b), (b, a)):
                i, j = int(mine.index()), int(other.index())
                if i in own and j not in own and j not in ignored:
                    touched.add((mine.name(), other.name()))
        return sorted(touched)

    def _held_part(self) -> str:
        """The part this arm's gripper holds ("" when none, or no gripper)."""
        runtime = self._runtime
        return runtime.gripper_state(self.name).part if self.name in runtime.station.grippers else ""

    @functools.cached_property
    def _contact_bodies(self) -> tuple[set[int], dict[str, int]]:
        """Body indices (fixed once the station is built): the arm's and its
        gripper's, and the parts' by name."""
        station = self._runtime.station
        plant = station.plant
        handles = station.arm(self.name)
        own = {int(b) for b in plant.GetBodyIndices(handles.arm)}
        if handles.gripper is not None:
            own |= {int(b) for b in plant.GetBodyIndices(handles.gripper)}
        parts = {n: int(plant.GetBodyByName(n, i).index()) for n, i in station.parts.items()}
        return own, parts

    def start(self, plan: Plan) -> float:
        """Hands ``plan`` to the arm's commander from now; returns the start time."""
        commander = self._commander
        context = commander.GetMyMutableContextFromRoot(self._runtime.context)
        start = self._runtime.time
        # The plan's first sample is where the arm is; the commander takes over from it.
        commander.command(
            context,
            JointCommand(q=commander.commanded_position(context), trajectory=plan.trajectory, t0=start),
        )
        return start

    def teleport(self, q: np.ndarray) -> None:
        """Puts the arm at rest at ``q`` now and commands it to hold there (no motion)."""
        runtime = self._runtime
        runtime.station.set_arm_positions(runtime.context, self.name, q)
        self._commander.hold(self._commander.GetMyMutableContextFromRoot(runtime.context), q)

    def run(self, plan: Plan, until: Optional[Callable[[], bool]]) -> MoveResult:
        """Runs ``plan`` from now to its end (and until the arm has settled), or
        until ``until()`` holds; checks the arm's contacts on the way."""
        runtime = self._runtime
        commander = self._commander
        context = commander.GetMyMutableContextFromRoot(runtime.context)
        start = self.start(plan)
        end = start + plan.duration
        period = GUARD_PERIOD if until is not None else CONTACT_CHECK_PERIOD
        stopped = False
        next_contact_check = start + CONTACT_CHECK_PERIOD
        while runtime.time < end - 1e-9:
            runtime.advance_to(min(end, runtime.time + period))
            if runtime.time >= next_contact_check - 1e-9 or runtime.time >= end - 1e-9:
                self._check_contacts()
                next_contact_check = runtime.time + CONTACT_CHECK_PERIOD
            self._between_steps()
            if until is not None and until():
                stopped = True
                self._stop(context)
                break
        goal = commander.current(context).at(math.inf)
        settle_end = runtime.time + SETTLE_TIMEOUT
        while (
            not stopped
            and np.max(np.abs(self._joint_values() - goal)) > SETTLE_TOLERANCE
            and runtime.time < settle_end - 1e-9
        ):
            runtime.advance_to(min(settle_end, runtime.time + GUARD_PERIOD))
            self._check_contacts()
            self._between_steps()
        return MoveResult(start, runtime.time, stopped, self._joint_values())

    def _between_steps(self) -> None:
        """The cell's move-step hooks (see :meth:`Cell.on_move_step
        <omtp_drake.script.cell.Cell.on_move_step>`)."""
        for hook in self._step_hooks:
            hook()

    def _stop(self, context: Context) -> None:
        """Decelerates from the commanded motion to rest over :data:`STOP_TIME`."""
        command = self._commander.current(context)
        t = self._runtime.time
        q = command.at(t)
        if command.trajectory is None:
            return
        tau = min(max(t - command.t0, command.trajectory.start_time()), command.trajectory.end_time())
        v = command.trajectory.EvalDerivative(tau, 1).ravel()
        q_rest = q + 0.5 * v * STOP_TIME
        stop = PiecewisePolynomial.CubicHermite(
            [0.0, STOP_TIME], np.column_stack([q, q_rest]), np.column_stack([v, np.zeros_like(v)])
        )
        self._commander.command(context, replace(command, trajectory=stop, t0=t))
        self._runtime.advance(STOP_TIME)

    def _check_contacts(self) -> None:
        """Raises CollisionError if the arm or its gripper touches anything but a
        loose part (see :meth:`contacts`)."""
        touched = self.contacts()
        if not touched:
            return
        context = self._commander.GetMyMutableContextFromRoot(self._runtime.context)
        self._commander.command(context, JointCommand(q=self._joint_values()))
        pairs = ", ".join(f"{a} - {b}" for a, b in touched)
        raise CollisionError(
            f"t={self._runtime.time:.2f} s: {self.name} touched something it should not: {pairs}; "
            "it stopped there"
        )
