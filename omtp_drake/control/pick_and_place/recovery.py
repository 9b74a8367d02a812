"""The pick-and-place machine's tool paths and the ends of failed attempts.

:class:`Moves` plans the task's travels (clearing the bin's rim) and the way Home;
:class:`Recovery` ends an attempt that failed (the arm goes Home to retry, or the
part is given up after its last attempt), a part lost or dropped into the bin, and
a full bin. Both serve :class:`~omtp_drake.control.pick_and_place.machine.PickMachine`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Optional

from pydrake.math import RigidTransform

from omtp_drake.control.pick_and_place.controller_state import (
    ControlState,
    Mode,
    PickFailure,
    PickRecord,
    position_of,
)
from omtp_drake.control.pick_and_place.machine_io import MachineInput
from omtp_drake.control.pick_and_place.perception import Perception, Sighting
from omtp_drake.control.pick_policy import PickPlanner
from omtp_drake.control.tool_paths import Path
from omtp_drake.scenario import BinConfig, TaskConfig

#: A handler's answer: the next control state and, when an attempt ended, its record.
Step = tuple[ControlState, Optional[PickRecord]]


def go(s: ControlState, mode: Mode, t: float, **changes) -> ControlState:
    """``s`` in ``mode`` from ``t`` on, with ``changes``."""
    return replace(s, mode=mode, mode_start=t, **changes)


class Moves:
    """The task's tool paths: travels that clear the bin's rim, the way Home."""

    def __init__(
        self,
        planner: PickPlanner,
        see: Perception,
        bin: BinConfig,
        X_W_home: RigidTransform,
        wrist_home: float,
    ) -> None:
        self.planner = planner
        self._see = see
        self._bin = bin
        self._X_W_home = X_W_home
        self._wrist_home = wrist_home

    def wrist(self, inputs: MachineInput) -> float:
        """The last wrist joint's measured angle from its home angle (rad)."""
        return inputs.q[5] - self._wrist_home

    def bin_pose(self, inputs: MachineInput) -> RigidTransform:
        """``X_WBin``: where the bin camera last saw the bin, else the scenario's pose."""
        return self._see.bin_pose(inputs.bin_image)

    def travel(
        self,
        inputs: MachineInput,
        X_goal: RigidTransform,
        size: float,
        min_height: float = -math.inf,
        **clear: Optional[float],
    ) -> Path:
        """From the tool's pose now: up, an arc, down (see PickPlanner.travel, which
        gets ``clear_start`` and ``clear_end``), at least ``min_height`` high and high
        enough near the bin for a part of edge ``size`` under the tool to clear its rim."""
        X_now = inputs.X_WE
        rim = self.planner.clearance_height(
            self.bin_pose(inputs), self._bin.geometry, size, [X_now.translation(), X_goal.translation()]
        )
        return self.planner.travel(inputs.t, X_now, X_goal, max(rim, min_height), **clear)

    def home(self, inputs: MachineInput, size: float) -> Path:
        """The travel Home (turned to keep the wrist wound less than half a turn)."""
        X_home = self.planner.home_pose(self._X_W_home, inputs.X_WE, self.wrist(inputs))
        return self.travel(inputs, X_home, size)


class Recovery:
    """Ends of failed attempts: a failure (the arm goes Home to retry, or gives the
    part up after its last attempt), a part lost or dropped into the bin, a full bin."""

    def __init__(
        self, config: TaskConfig, see: Perception, moves: Moves, part_size: Callable[[str], float]
    ) -> None:
        self._config = config
        self._see = see
        self._moves = moves
        self._size = part_size

    def fail(
        self, inputs: MachineInput, s: ControlState, reason: PickFailure, *, reset_ik: bool = False
    ) -> Step:
        """Records a failed attempt and sends the arm Home (suction off); with
        ``reset_ik`` DiffIK restarts from the measured joints first."""
        t = inputs.t
        if reason is PickFailure.DROPPED and s.part:  # last known: under the cup when it fell
            size = self._size(s.part)
            s = replace(s, X_WP=RigidTransform(inputs.X_WE.translation() - [0.0, 0.0, size / 2]))
        attempt = s.attempt + 1 if s.part else 1
        ignored = s.ignored
        given_up = bool(s.part) and attempt > self._config.max_attempts
        if given_up:  # its last attempt: left where it was last known
            ignored = ignored + (s.part,)
            attempt = 1
        position = position_of(s.X_WP) if given_up else None
        record = PickRecord(s.part, s.pick_start, t, False, reason, s.attempt, position, given_up)
        path = self._moves.home(inputs, self._size(s.part) if s.part else 0.0)
        # A drop is recorded once where the part came to rest is known (see landed()).
        pending = record if reason is PickFailure.DROPPED and not given_up else None
        return go(
            s,
            Mode.HOME,
            t,
            attempt=attempt,
            ignored=ignored,
            suction=False,
            part="" if attempt == 1 else s.part,
            path=path,
            reset_ik=reset_ik,
            pending_drop=pending,
        ), (None if pending is not None else record)

    @staticmethod
    def landed(t: float, s: ControlState, X_WP: RigidTransform) -> Step:
        """The dropped part is seen at rest at ``X_WP`` at ``t``: its drop is recorded
        with where it landed, and the next attempt starts now (a retry after another
        failure counts from its first attempt; a drop has its own record's end)."""
        drop = s.pending_drop
        if drop is None:
            return s, None
        return replace(s, pending_drop=None, pick_start=t), replace(drop, position=position_of(X_WP))

    def lost(self, inputs: MachineInput, s: ControlState, name: str, mine: list[Sighting]) -> Optional[Step]:
        """Part ``name`` (being picked again, or the last one seen) is given up on when
        it fell into the bin (``dropped_into_bin``: in the bin, but not by a place),
        lies out of reach, or no camera has seen it for ``lost_timeout`` s (``lost``,
        where it was last seen); the record has its position. None while it may still
        be picked."""
        t = inputs.t
        last = s.X_WP if s.part else s.candidate_X
        in_bin = self._see.seen_in_bin(t, inputs.bin_image, name)
        if in_bin is not None:
            why, X_WP, placed = PickFailure.DROPPED_INTO_BIN, in_bin, s.placed + 1
        elif mine:
            at_rest = bool(s.part) or s.candidate_at_rest  # (a part seen for the first time may still roll)
            if self._see.reachable(mine[0][1], self._size(name)) or not at_rest:
                return None
            why, X_WP, placed = PickFailure.LOST, mine[0][1], s.placed
        elif math.isnan(s.missing_since) or t - s.missing_since < self._config.lost_timeout:
            return None
        else:
            why, X_WP, placed = PickFailure.LOST, last, s.placed
        start = s.pick_start if s.part else s.candidate_time
        attempt = s.attempt if s.part else 1
        record = PickRecord(name, start, t, False, why, attempt, position=position_of(X_WP), given_up=True)
        if s.pending_drop is not None and s.pending_drop.part == name:
            # Not a new attempt: where the drop ended (in the bin, or out of reach / unseen).
            reason = (
                PickFailure.DROPPED_INTO_BIN if why is PickFailure.DROPPED_INTO_BIN else PickFailure.DROPPED
            )
            record = replace(s.pending_drop, reason=reason, position=position_of(X_WP), given_up=True)
        return go(
            s,
            Mode.WAIT_PART,
            t,
            part="",
            attempt=1,
            ignored=s.ignored + (name,),
            placed=placed,
            last_seen=t,
            missing_since=math.nan,
            candidate="",
            candidate_X=None,
            candidate_time=math.nan,
            candidate_at_rest=False,
            pending_drop=None,
        ), record

    def bin_full(
        self, inputs: MachineInput, s: ControlState, name: str, X_WP: Optional[RigidTransform]
    ) -> Step:
        """No slot left for part ``name``: it is given up where it lies (let go if
        held), the arm goes Home and the machine stops (Mode.BIN_FULL)."""
        t = inputs.t
        start = s.pick_start if s.part == name else t
        record = PickRecord(
            name, start, t, False, PickFailure.BIN_FULL, s.attempt, position_of(X_WP), given_up=True
        )
        path = self._moves.home(inputs, self._size(name))
        state = go(
            s, Mode.BIN_FULL, t, part="", attempt=1, ignored=s.ignored + (name,), suction=False, path=path
        )
        return state, record
