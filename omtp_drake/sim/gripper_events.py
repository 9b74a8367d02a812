"""The vacuum grippers' events: a world edit of the driver that runs a gripper's rule
when something happens, and makes and removes a weld gripper's constraints.

The course's plugin looks at its command at every physics update; the result of
that look changes only when the command changes, when a contact check is due
(0.1 s after the last, ``updateRate``), when an injected fault begins or ends, and
(weld backend) one plant step after a check decided an attach. So a gripper whose
command services give (a script, ROS, FlexBE; its station input is free) never
polls: :meth:`GripperEvents.command` and :meth:`GripperEvents.fault` schedule its
rule (its forced event, ``ExecuteForcedEvents``) at the plant step at or
after the call, and while it is enabled the driver stops at each check that is due.
A gripper whose command a controller of the diagram writes polls it itself, one
plant step after each of the controller's updates
(:class:`~omtp_drake.cell.suction.CommandPolling`); the driver stops one step after
a check of it that may decide an attach, to make the weld. An idle gripper costs
nothing.

The constraints (:func:`~omtp_drake.cell.suction_holds.sync_weld`) follow each weld
gripper's state one plant step after a check decided an attach or a service's
disable released a part, and every ``IDLE_SYNC_PERIOD`` while a weld holds a part (a
release the controller commands, a fault's or a lost hold's is made at the next of
those), where the per-step poll made them before. While no weld holds a part the
driver does not stop for them: such a sync would find nothing to do.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Optional

from pydrake.systems.framework import Context

from omtp_drake.cell.suction import (
    CHECK_TOLERANCE,
    GripperMemory,
    SuctionGripper,
    memory_of,
    next_check_after,
)
from omtp_drake.cell.suction_holds import WeldSuctionGripper, sync_weld
from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

#: Times closer than this (s) are the same time.
_EPS = 1e-9
#: At least how often weld constraints follow the grippers' states [s]: a release
#: the controller commands (or a fault) is made within that time.
IDLE_SYNC_PERIOD = 0.05


class GripperEvents:
    """The grippers' rule runs and weld syncs between advances (module doc).

    A world edit (``period``: the weld's idle sync) with events of its own: the
    driver stops at :meth:`next_time` too, and calls :meth:`before_advance` before
    each advance (after the edits and callbacks at that time, where the gripper's
    periodic poll used to run)."""

    def __init__(self, station: Station):
        self._plant = station.plant
        self._grippers: dict[str, SuctionGripper] = dict(station.grippers)
        self._welds = [g for g in self._grippers.values() if isinstance(g, WeldSuctionGripper)]
        self._step = station.plant.time_step()
        #: Whether a weld gripper's constraints hold a part, or its state says it holds
        #: one they do not (a fresh Context): only then can the idle sync change anything.
        #: Both change only at a sync (here), never inside an advance.
        self._holding = False
        #: Grippers commanded by services (their rule runs here); the others poll.
        self._served: set[str] = {r for r, g in self._grippers.items() if g.polling is None}
        #: Times at which a gripper's rule is due (robot -> times), and weld syncs.
        self._runs: dict[str, list[float]] = {r: [] for r in self._grippers}
        self._syncs: list[float] = []
        #: (robot, gripper, whether it welds), in the grippers' order.
        self._kinds = [(r, g, isinstance(g, WeldSuctionGripper)) for r, g in self._grippers.items()]

    def serve(self, robots: Iterable[str]) -> None:
        """``robots``' grippers are commanded by services (their command inputs are
        free): their checks are scheduled here, whether or not they also poll."""
        self._served.update(robots)

    def check_driven(self, robots: Iterable[str]) -> None:
        """``robots``' gripper commands are written by a system of the diagram: each
        must poll (ConfigError otherwise: it would never see its command)."""
        deaf = sorted(r for r in robots if self._grippers[r].polling is None)
        if deaf:
            raise ConfigError(
                f"the gripper command of {', '.join(deaf)} is connected to a system of the diagram, "
                "but the station built the gripper for service commands (no polling); only the "
                "scenario's task robot's gripper is driven by a controller"
            )

    @property
    def period(self) -> float:
        """The idle sync's period while a weld holds a part (its release, whenever the
        gripper lets go, is made at the next multiple); inf while none does: a sync would
        find nothing to do, and an attach is made by a scheduled sync."""
        return IDLE_SYNC_PERIOD if self._holding else math.inf

    # ------------------------------------------------------------------ services

    def command(self, root_context: Context, robot: str) -> None:
        """``robot``'s command input was just set: its rule runs at the plant step at or
        after now (where the plugin's next physics update would see it)."""
        self._runs[robot].append(_step_at_or_after(self._step, root_context.get_time()))

    def fault(self, root_context: Context, robot: str, until: float) -> None:
        """``robot``'s vacuum just failed until ``until``: its rule runs at the plant steps
        at or after now and at or after ``until``. A gripper that polls sees the start
        itself, at its next poll: events of the diagram due now (its controller's
        update) still see the part held, as they did beside the per-step poll."""
        if robot in self._served:
            self._runs[robot].append(_step_at_or_after(self._step, root_context.get_time()))
        self._runs[robot].append(_step_at_or_after(self._step, until))

    # ------------------------------------------------------------------ the driver's

    def _in(self, root_context: Context) -> list[tuple[str, SuctionGripper, Context, bool]]:
        """Each gripper's robot, the gripper, its Context in ``root_context`` and whether
        it welds."""
        return [(r, g, g.GetMyMutableContextFromRoot(root_context), weld) for r, g, weld in self._kinds]

    def next_time(self, root_context: Context) -> float:
        """The next time (after now) one of these events is due."""
        now = root_context.get_time()
        after = now + _EPS
        first = math.inf
        for runs in self._runs.values():
            first = _first_after(runs, after, first)
        first = _first_after(self._syncs, after, first)
        for robot, gripper, context, weld in self._in(root_context):
            memory = memory_of(gripper, context)
            driver = self._driver_check(robot, gripper, memory)
            if after < driver < first:
                first = driver
            if weld and memory.pending_body >= 0:
                # An attach already decided: its weld one step after the deciding check,
                # also when the driver stopped inside that step (a caller's stop).
                sync = _pending_sync(memory, self._step)
                if after < sync < first:
                    first = sync
                continue
            # A check on the gripper's own poll that may decide an attach: the weld one
            # step later (after a check the driver runs, before_advance schedules it).
            polled = robot not in self._served and driver == math.inf
            if polled and weld and self._may_decide(gripper, context, memory):
                check = max(
                    _poll_at_or_after(gripper, next_check_after(gripper, memory), CHECK_TOLERANCE),
                    _poll_at_or_after(gripper, now),
                )
                sync = _step_after(check, self._step)
                if after < sync < first:
                    first = sync
        return first

    def _driver_check(self, robot: str, gripper: SuctionGripper, memory: GripperMemory) -> float:
        """When the driver runs the enabled gripper's next contact check (the plant step
        at or after ``1 / check_rate_hz`` after the last; ``memory``: the gripper's now):
        always for a gripper commanded by services, and for a polling one when that step
        is not one of its polls (its last check was the driver's: at a fault's end); inf
        otherwise."""
        if not memory.state.enabled:
            return math.inf
        due = _step_at_or_after(self._step, next_check_after(gripper, memory), CHECK_TOLERANCE)
        if robot in self._served or abs(_poll_at_or_after(gripper, due) - due) > _EPS:
            return due
        return math.inf

    @staticmethod
    def _may_decide(gripper: WeldSuctionGripper, context: Context, memory: GripperMemory) -> bool:
        """Whether the gripper's next check may decide an attach: not holding, none
        pending (``memory``: the gripper's now), enabled by its command now."""
        if memory.state.attached or memory.pending_body >= 0:
            return False
        return bool(gripper.command_input_port().Eval(context)[0] > 0.5)

    def before_advance(self, root_context: Context) -> None:
        """Runs each gripper's rule that is due now: a command, a fault's start or end,
        a served gripper's check; schedules the weld sync one step later where the
        rule decided an attach or a disable released a part."""
        now = root_context.get_time()
        after = now + _EPS
        found = self._in(root_context)
        memories = self._overdue_attaches(root_context, after, found)
        for i, (robot, gripper, context, weld) in enumerate(found):
            runs = self._runs[robot]
            due = False
            if runs:
                due = any(t <= after for t in runs)
                if due:
                    self._runs[robot] = [t for t in runs if t > after]
            memory = memories[i] if memories is not None else memory_of(gripper, context)
            due = due or self._driver_check(robot, gripper, memory) <= after
            if not due:
                continue
            gripper.ExecuteForcedEvents(context)
            if weld and self._needs_sync(gripper, context, root_context):
                self._syncs.append(_step_after(now, self._step))

    def _overdue_attaches(
        self, root_context: Context, after: float, found: list[tuple[str, SuctionGripper, Context, bool]]
    ) -> Optional[list[GripperMemory]]:
        """Makes now a decided attach whose step has passed without a stop (a check no
        stop announced: the command switched on inside an advance and the first check
        decided, ``consecutive_checks: 1``), instead of never; the idle sync then runs
        while it holds, as after an attach made at its step. Returns the grippers'
        memories (as ``found``) when it made none, else None (a sync changes them)."""
        memories = []
        synced = False
        for _robot, gripper, context, weld in found:
            memory = memory_of(gripper, context)
            memories.append(memory)
            if weld and memory.pending_body >= 0 and _pending_sync(memory, self._step) <= after:
                sync_weld(gripper, self._plant, root_context)
                self._holding = self._any_holding(root_context)
                synced = True
        return None if synced else memories

    def _needs_sync(self, gripper: WeldSuctionGripper, context: Context, root_context: Context) -> bool:
        """After a rule run: an attach is pending, or the command's disable released a
        held part (a fault's release waits for the idle sync, as a controller's)."""
        if gripper.pending_part(context):
            return True
        if gripper.get_state(context).attached or gripper.command_input_port().Eval(context)[0] > 0.5:
            return False
        plant_context = self._plant.GetMyContextFromRoot(root_context)
        return gripper.constraints.held_body(self._plant, plant_context) is not None

    def __call__(self, root_context: Context) -> None:
        """At a stop: the weld constraints follow the grippers' states: all of them at
        the idle sync's period and one step after a service's rule run; at a stop one
        step after a check, only a pending attach is made (a part a fault or a lost
        hold let go is released at the idle sync, as a controller's disable)."""
        now = root_context.get_time()
        scheduled = any(abs(t - now) <= _EPS for t in self._syncs)
        self._syncs = [t for t in self._syncs if t > now + _EPS]
        every = scheduled or _is_multiple(now, IDLE_SYNC_PERIOD)
        synced = False
        for gripper in self._welds:
            if every or gripper.pending_part(gripper.GetMyContextFromRoot(root_context)):
                sync_weld(gripper, self._plant, root_context)
                synced = True
        if synced:
            self._holding = self._any_holding(root_context)

    def _any_holding(self, root_context: Context) -> bool:
        """Whether a weld gripper's constraints hold a part or its state says attached."""
        plant_context = self._plant.GetMyContextFromRoot(root_context)
        return any(
            g.constraints.held_body(self._plant, plant_context) is not None
            or g.get_state(g.GetMyContextFromRoot(root_context)).attached
            for g in self._welds
        )


def _first_after(times: list[float], after: float, first: float) -> float:
    """The earliest of ``first`` and the ``times`` later than ``after``."""
    for t in times:
        if after < t < first:
            first = t
    return first


def _step_at_or_after(step: float, t: float, tolerance: float = 0.0) -> float:
    """The first plant step time ``k h`` (as Drake computes it) at or after ``t -
    tolerance``. Without tolerance the comparison is exact: a step a rounding error
    before ``t`` has already been taken when the simulator stops at ``t``."""
    return _first_sample(0.0, step, t - tolerance)


def _poll_at_or_after(gripper: SuctionGripper, t: float, tolerance: float = 0.0) -> float:
    """The first of the gripper's own polls at or after ``t - tolerance``, a poll a
    rounding error before it included (inf without polling)."""
    if gripper.polling is None:
        return math.inf
    period, offset = gripper.polling.period, gripper.polling.offset
    if t == -math.inf:
        return offset
    return offset + max(0, math.ceil((t - tolerance - offset) / period - 1e-6)) * period


def _first_sample(offset: float, period: float, t: float) -> float:
    """The first ``offset + k period`` (k >= 0, computed as Drake computes a periodic
    event's times) that is >= ``t``, compared exactly (``offset`` for ``t`` = -inf)."""
    if t == -math.inf:
        return offset
    k = max(0, math.ceil((t - offset) / period - 1e-6))
    while k > 0 and offset + (k - 1) * period >= t:
        k -= 1
    while offset + k * period < t:
        k += 1
    return offset + k * period


def _pending_sync(memory: GripperMemory, step: float) -> float:
    """When the attach ``memory`` holds pending is made: one plant step after the check
    that decided it."""
    return _step_after(memory.pending_since, step)


def _step_after(t: float, step: float) -> float:
    """The plant step after ``t``, as the driver computes its next stop (one step
    after a rule's run, where the per-step poll's sync made the weld)."""
    return (math.floor(t / step + _EPS) + 1) * step


def _is_multiple(t: float, period: float) -> bool:
    """Whether ``t`` is a multiple of ``period`` (as the driver decides it)."""
    if math.isinf(period):
        return False
    k = round(t / period)
    return abs(k * period - t) < _EPS * max(1.0, abs(t))
