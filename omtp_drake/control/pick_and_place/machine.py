"""The pick-and-place state machine of one robot, in plain values.

:class:`PickMachine` takes one :class:`MachineInput` per update (the time, the
cameras' images, the gripper's state, the measured tool pose and joint positions)
and the control state, and returns a :class:`Decision` (the next control state: its
mode, the tool path to follow, suction on or off; and the record of an attempt that
ended). It knows nothing of Drake systems: the
:class:`~omtp_drake.control.pick_and_place.system.PickAndPlaceController` reads its
ports into a MachineInput and writes the Decision into its state.

Cycle (one handler per :class:`~omtp_drake.control.pick_and_place.controller_state.Mode`)::

    WAIT_PART -> APPROACH (above the part, tool down, yaw matched)
      -> DESCEND (straight down until the cup face meets the top face)
      -> ATTACH (suction on, wait for `attached`; timeout -> retry)
      -> TRANSFER (up by the approach height, an arc about the robot's base, down
         into the bin: one blended motion)
      -> RELEASE (suction off; the bin camera must see it inside; meanwhile the
         pick camera watches for the next part)
      -> WAIT_PART (after a failure: HOME first)

A part for which the bin has no slot left (where the arm reaches) is given up
(``bin_full``) and the machine stops in BIN_FULL: the task cannot finish.

Recovery, each recorded with its reason: suction does not attach
(``attach_timeout``); part dropped in transit (``dropped``); no part seen
(``no_part``); DiffIK cannot follow (``tracking``: DiffIK restarts from the
measured joints); part not in the bin after release (``missed_bin``). After a
failure the arm goes Home and retries, up to ``max_attempts`` per part; after the
last one (and after ``lost`` or ``dropped_into_bin``) the part is given up: its
record says so and where it lies, and the task's spawner replaces it.

The bin is where the bin camera last saw it (the scenario's pose until then):
a bin moved after a plan is found again for the next one.

Frames: W world, E ``<gripper>_tip`` (the cup face, +z out of the tool), P a
part's origin (its centre), Bin the bin's origin.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import replace
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell import arms
from omtp_drake.control.pick_and_place.controller_state import ControlState, Mode, PickFailure, PickRecord
from omtp_drake.control.pick_and_place.machine_io import NO_IMAGE, Decision, MachineInput
from omtp_drake.control.pick_and_place.perception import Perception, Sighting
from omtp_drake.control.pick_and_place.recovery import Moves, Recovery, Step, go
from omtp_drake.control.pick_policy import PickPlanner
from omtp_drake.control.tool_paths import Path, SegmentKind, hold, yaw_of
from omtp_drake.scenario import BinConfig, RobotConfig, Scenario, TaskConfig

__all__ = [
    "NO_IMAGE",
    "Decision",
    "MachineInput",
    "PickMachine",
    "bin_capacity",
    "task_planner",
    "travel_check",
]


#: The modes whose handler only waits for the end of the path the arm follows.
_TRAVEL = frozenset({Mode.APPROACH, Mode.DESCEND, Mode.TRANSFER, Mode.HOME})


def _tracks(s: ControlState) -> bool:
    """Whether the tracking check runs in ``s``'s mode (not while pressing into a part)."""
    return s.mode not in (Mode.DESCEND, Mode.ATTACH)


def _tracking_error(X_WE_desired: RigidTransform, X_WE: RigidTransform) -> float:
    """How far (m) the tool is from where its path wants it."""
    d = X_WE_desired.translation() - X_WE.translation()
    return math.sqrt(d.dot(d))  # np.linalg.norm's very sum, without its checks


def travel_check(
    s: ControlState,
    t: float,
    tolerance: float,
    attached: Callable[[], bool],
    desired: Callable[[], Optional[RigidTransform]],
    X_now: Callable[[], RigidTransform],
) -> Optional[float]:
    """The checks of every mode (:meth:`PickMachine._watch`) at an update where the arm
    travels with nothing else to decide: the mode's handler only waits for its path's end
    (after ``t``), no DiffIK restart is pending and no tracking failure is counting.
    Returns the tracking error (m) if :meth:`PickMachine.step` would return ``s`` itself
    and no record (a carried part still ``attached()``, the tool ``X_now()`` within
    ``tolerance`` of ``desired()``, the pose table's ``X_WE`` at ``t`` or None), else None:
    the caller runs the step. Reads each input only if it needs it."""
    if s.mode not in _TRAVEL or s.reset_ik or not math.isnan(s.bad_tracking_since) or s.path.done(t):
        return None
    if s.mode is Mode.TRANSFER and not attached():
        return None
    if not _tracks(s):
        return 0.0
    X_WE_desired = desired()
    error = _tracking_error(X_WE_desired if X_WE_desired is not None else s.pose_at(t), X_now())
    return None if error > tolerance else error


def task_planner(config: TaskConfig, robot: RobotConfig) -> PickPlanner:
    """The tool-path planner of ``robot`` for ``config``: slots within the arm's reach."""
    return PickPlanner(
        arms.base_pose(robot),
        config.max_tool_speed,
        config.transfer_clearance,
        config.grid,
        reach=lambda z: arms.tool_down_reach(robot, z),
    )


def bin_capacity(scenario: Scenario) -> int:
    """How many of the scenario's parts its task's bin holds where its robot reaches."""
    task = scenario.required_task()
    size = (
        scenario.pool_part_size
        if scenario.part_pool
        else max((p.size for p in scenario.parts), default=scenario.pool_part_size)
    )
    b = scenario.bin(task.bin)
    return len(task_planner(task, scenario.robot(task.robot)).slots(b.X_WB(), b.geometry, size))


def _note_candidate(s: ControlState, name: str, X_WP: RigidTransform, stamp: float) -> ControlState:
    """Records a sighting of the next part (from an image not seen before): at
    rest if the previous sighting was of the same part within 3 mm."""
    if stamp == s.candidate_time:
        return s
    at_rest = (
        s.candidate == name
        and s.candidate_X is not None
        and np.linalg.norm(s.candidate_X.translation() - X_WP.translation()) <= 0.003
    )
    return replace(s, candidate=name, candidate_X=X_WP, candidate_time=stamp, candidate_at_rest=at_rest)


class PickMachine:
    """The pick-and-place decisions of one robot (see the module doc).

    Args:
        config: the task.
        robot: the picking arm.
        bin: the bin parts go into.
        part_size: a part's edge (m) by name.
        X_W_home: the tool's pose at the arm's Home joint positions.
    """

    def __init__(
        self,
        config: TaskConfig,
        robot: RobotConfig,
        bin: BinConfig,
        part_size: Callable[[str], float],
        X_W_home: RigidTransform,
    ) -> None:
        config.validate()
        self._config = config
        self._bin = bin
        self._size = part_size
        self._see = Perception(config, robot, bin, part_size)
        self._planner = task_planner(config, robot)
        wrist_home = float(arms.named_pose("Home", robot)[5])
        self._moves = Moves(self._planner, self._see, bin, X_W_home, wrist_home)
        self._recovery = Recovery(config, self._see, self._moves, part_size)
        self._handlers: dict[Mode, Callable[[MachineInput, ControlState], Step]] = {
            Mode.INIT: self._init,
            Mode.WAIT_PART: self._wait_part,
            Mode.APPROACH: self._approach,
            Mode.DESCEND: self._descend,
            Mode.ATTACH: self._attach,
            Mode.TRANSFER: self._transfer,
            Mode.RELEASE: self._release,
            Mode.HOME: self._home,
            Mode.BIN_FULL: lambda inputs, s: (s, None),
        }

    def step(self, inputs: MachineInput, s: ControlState) -> Decision:
        """One update: the checks of every mode, then the current mode's handler."""
        if s.reset_ik:  # DiffIK has restarted from the measured joints by now
            s = replace(s, reset_ik=False)
        new, record, error = self._watch(inputs, s)
        if record is None:
            new, record = self._handlers[new.mode](inputs, new)
        return Decision(new, record, error)

    # ------------------------------------------------------------- helpers

    def _parts_seen(self, inputs: MachineInput, s: ControlState) -> Optional[Iterator[Sighting]]:
        """The parts to pick, one by one (see Perception.parts_seen); None: no fresh image."""
        return self._see.parts_seen(
            inputs.t,
            inputs.pick_image,
            lambda: (inputs.bin_image, *inputs.search_images),
            lambda: inputs.bin_image,
            s.ignored,
        )

    # --------------------------------------------------------------- checks

    def _watch(
        self, inputs: MachineInput, s: ControlState
    ) -> tuple[ControlState, Optional[PickRecord], float]:
        """The checks of every mode: DiffIK keeps up with the plan (outside the
        descent, which presses into the part), a carried part stays attached.
        Returns the state, a failure record if one ended the attempt, and the
        tracking error (m)."""
        t, X_now = inputs.t, inputs.X_WE
        desired = inputs.X_WE_desired if inputs.X_WE_desired is not None else s.pose_at(t)
        error = 0.0
        if desired is not None and _tracks(s):
            error = _tracking_error(desired, X_now)
            if error > self._config.tracking_tolerance:
                if math.isnan(s.bad_tracking_since):
                    s = replace(s, bad_tracking_since=t)
                elif t - s.bad_tracking_since > self._config.tracking_time:
                    s = replace(s, bad_tracking_since=math.nan)
                    return (*self._recovery.fail(inputs, s, PickFailure.TRACKING, reset_ik=True), error)
            elif not math.isnan(s.bad_tracking_since):
                s = replace(s, bad_tracking_since=math.nan)
        if s.mode is Mode.TRANSFER and not inputs.gripper.attached:
            return (*self._recovery.fail(inputs, s, PickFailure.DROPPED), error)
        return s, None, error

    # ------------------------------------------------------------- handlers

    def _init(self, inputs: MachineInput, s: ControlState) -> Step:
        return go(s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t, path=hold(inputs.t, inputs.X_WE)), None

    def _wait_part(self, inputs: MachineInput, s: ControlState) -> Step:
        """Plan a pick as soon as a part is seen at rest (same pose in two images)."""
        t = inputs.t
        sightings = self._parts_seen(inputs, s)
        if sightings is None:
            return s, None  # camera image missing: wait
        seen = list(sightings)
        # The part being picked again, or the one seen last: is it still somewhere?
        tracked = s.part or (s.candidate if s.candidate not in s.ignored else "")
        mine = [x for x in seen if x[0] == tracked] if tracked else []
        if tracked:
            lost = self._recovery.lost(inputs, s, tracked, mine)
            if lost is not None:
                return lost
            if not mine and math.isnan(s.missing_since):
                s = replace(s, missing_since=t)
            elif mine and not math.isnan(s.missing_since):
                s = replace(s, missing_since=math.nan)
        if s.part:
            if not mine:
                return s, None
            seen = mine
        reachable = [x for x in seen if self._see.reachable(x[1], self._size(x[0]))]
        if not reachable and seen:
            # Only parts the arm cannot reach: watch one; once it is at rest it is
            # given up as lost (see Recovery.lost), so the spawner may replace it.
            return _note_candidate(s, *seen[0]), None
        if not reachable:
            if t - s.last_seen > self._config.detect_timeout:
                return go(s, Mode.WAIT_PART, t, last_seen=t), PickRecord(
                    "", t, t, False, PickFailure.NO_PART, 1
                )
            return s, None
        name, X_WP, stamp = reachable[0]
        if stamp != s.candidate_time:
            s = replace(_note_candidate(s, name, X_WP, stamp), last_seen=t)
        if not (s.candidate == name and s.candidate_at_rest):
            return s, None
        if s.pending_drop is not None and s.pending_drop.part == name:
            return self._recovery.landed(t, s, X_WP)  # the pick is planned at the next update
        return self._plan_pick(inputs, s, name, X_WP)

    def _plan_pick(self, inputs: MachineInput, s: ControlState, name: str, X_WP: RigidTransform) -> Step:
        """Travel above part ``name`` (at rest at ``X_WP``), if the bin has a slot for it."""
        t, size = inputs.t, self._size(name)
        if self._planner.slot(self._moves.bin_pose(inputs), self._bin.geometry, size, s.placed) is None:
            return self._recovery.bin_full(inputs, s, name, X_WP)
        start = s.pick_start if (s.part == name and s.attempt > 1) else t
        X_above = self._planner.grasp_pose(
            X_WP, size, inputs.X_WE, self._config.approach_height, self._moves.wrist(inputs)
        )
        # The cup is empty: it may leave and arrive on a curve (it stays above the
        # rim it starts over and above the approach height at the part).
        path = self._moves.travel(inputs, X_above, size, clear_start=0.0, clear_end=0.0)
        return go(
            s,
            Mode.APPROACH,
            t,
            part=name,
            X_WP=X_WP,
            pick_start=start,
            path=path,
            last_seen=t,
            missing_since=math.nan,
        ), None

    def _approach(self, inputs: MachineInput, s: ControlState) -> Step:
        """Above the part: look again (it may have moved since the plan), go down."""
        t, c = inputs.t, self._config
        if not s.path.done(t):
            return s, None
        X_WP = s.X_WP
        for name, X, _ in self._parts_seen(inputs, s) or []:
            if name == s.part:
                X_WP = X
                break
        size = self._size(s.part)
        X_touch = self._planner.grasp_pose(X_WP, size, inputs.X_WE, -c.press_depth)
        X_near = self._planner.grasp_pose(X_WP, size, inputs.X_WE, c.slow_zone)
        fast = self._planner.move(SegmentKind.LINE, t, inputs.X_WE, X_near)
        slow = self._planner.move(SegmentKind.LINE, fast.t1, X_near, X_touch, c.descent_speed)
        return go(s, Mode.DESCEND, t, X_WP=X_WP, path=Path((fast, slow))), None

    def _descend(self, inputs: MachineInput, s: ControlState) -> Step:
        if not s.path.done(inputs.t):
            return s, None
        return go(s, Mode.ATTACH, inputs.t, suction=True), None

    def _attach(self, inputs: MachineInput, s: ControlState) -> Step:
        t, c = inputs.t, self._config
        if inputs.gripper.attached and inputs.gripper.part == s.part:
            X_WBin = self._moves.bin_pose(inputs)
            size = self._size(s.part)
            p_slot = self._planner.slot(X_WBin, self._bin.geometry, size, s.placed)
            if p_slot is None:  # the bin holds no more the arm can reach: let go of it here
                return self._recovery.bin_full(inputs, s, s.part, s.X_WP)
            X_drop = self._planner.drop_pose(inputs.X_WE, p_slot, yaw_of(X_WBin), self._moves.wrist(inputs))
            # Straight up by the approach height before any sideways motion: the
            # part clears what it lay on (the belt's rails, its neighbours).
            lift = inputs.X_WE.translation()[2] + c.approach_height
            path = self._moves.travel(inputs, X_drop, size, min_height=lift, clear_start=c.approach_height)
            return go(s, Mode.TRANSFER, t, path=path), None
        if t - s.mode_start > c.attach_timeout:
            return self._recovery.fail(inputs, s, PickFailure.ATTACH_TIMEOUT)
        return s, None

    def _transfer(self, inputs: MachineInput, s: ControlState) -> Step:
        if not s.path.done(inputs.t):
            return s, None
        return go(s, Mode.RELEASE, inputs.t, suction=False), None

    def _release(self, inputs: MachineInput, s: ControlState) -> Step:
        """Suction off; once the part has settled, the bin camera decides."""
        t = inputs.t
        s = self._watch_for_next(inputs, s)
        if inputs.gripper.attached or t - s.mode_start < self._config.settle_time:
            return s, None
        verdict = self._see.in_bin(inputs.bin_image, s.part, s.mode_start)
        if verdict is None and self._config.bin_camera:
            return s, None  # no bin image taken after the release yet: wait
        success = verdict is not False
        record = PickRecord(
            s.part, s.pick_start, t, success, None if success else PickFailure.MISSED_BIN, s.attempt
        )
        if not success:
            return self._recovery.fail(inputs, s, PickFailure.MISSED_BIN)[0], record
        # Straight on to the next part (Home only after a failure).
        return go(
            s,
            Mode.WAIT_PART,
            t,
            part="",
            attempt=1,
            placed=s.placed + 1,
            ignored=s.ignored + (s.part,),
            last_seen=t,
            path=hold(t, inputs.X_WE),
        ), record

    def _watch_for_next(self, inputs: MachineInput, s: ControlState) -> ControlState:
        """Notes the next part the pick camera shows (not the one being released), so
        that WAIT_PART may plan at once if it is at rest."""
        for name, X_WP, stamp in self._parts_seen(inputs, s) or []:
            if name != s.part and self._see.reachable(X_WP, self._size(name)):
                return _note_candidate(s, name, X_WP, stamp)
        return s

    def _home(self, inputs: MachineInput, s: ControlState) -> Step:
        if not s.path.done(inputs.t):
            return s, None
        return go(s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t), None
