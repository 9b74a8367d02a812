"""The pick-and-place state machine of one robot, in plain values.

:class:`PickMachine` takes one :class:`MachineInput` per update (the time, the
cameras' images, the gripper's state, the measured tool pose and joint positions)
and the control state, and returns a :class:`Decision` (the next control state: its
mode, the tool path to follow, suction on or off; and the record of an attempt that
ended). It knows nothing of Drake systems: the
:class:`~omtp_drake.control.pick_and_place.system.PickAndPlaceController` reads its
ports into a MachineInput and writes the Decision into its state.

Cycle (one handler per :class:`~omtp_drake.control.pick_and_place.records.Mode`)::

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
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell import arms
from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.pick_and_place.perception import Perception, Sighting
from omtp_drake.control.pick_and_place.records import ControlState, Mode, PickFailure, PickRecord, position_of
from omtp_drake.control.pick_policy import PickPlanner
from omtp_drake.control.tool_paths import Path, SegmentKind, hold, yaw_of
from omtp_drake.scenario import BinConfig, RobotConfig, Scenario, TaskConfig

#: The image of a camera that has taken none (time NaN, nothing in view).
NO_IMAGE = LogicalCameraImage(math.nan, "", RigidTransform(), ())


def _no_image() -> LogicalCameraImage:
    return NO_IMAGE


@dataclass(frozen=True)
class MachineInput:
    """What one update sees.

    The camera images are read when the machine first asks for one (most modes
    never look: a moving arm follows its path), through the ``read_*`` functions,
    once per update; :meth:`seeing` makes an input of images in hand.

    Attributes:
        t: the time (s).
        X_WE: the tool's pose at the measured joint positions.
        gripper: the gripper's state (``attached``, the held ``part``).
        q: the arm's measured joint positions (rad), pan ... wrist 3.
        pick_image: the pick camera's latest image.
        bin_image: the bin camera's latest image (:data:`NO_IMAGE` without one).
        search_images: the other cameras' latest images.
        X_WE_desired: the control state's path at ``t``, when the caller has it at
            hand (the controller's pose table for DiffIK); None: the machine
            evaluates the path itself.
    """

    t: float
    X_WE: RigidTransform
    gripper: GripperState
    q: tuple[float, ...]
    read_pick_image: Callable[[], LogicalCameraImage] = field(default=_no_image, repr=False)
    read_bin_image: Callable[[], LogicalCameraImage] = field(default=_no_image, repr=False)
    read_search_images: Callable[[], tuple[LogicalCameraImage, ...]] = field(default=tuple, repr=False)
    X_WE_desired: Optional[RigidTransform] = None

    @classmethod
    def seeing(
        cls,
        t: float,
        X_WE: RigidTransform,
        gripper: GripperState,
        q: tuple[float, ...],
        pick_image: LogicalCameraImage = NO_IMAGE,
        bin_image: LogicalCameraImage = NO_IMAGE,
        search_images: tuple[LogicalCameraImage, ...] = (),
    ) -> MachineInput:
        """An input with these images."""
        return cls(t, X_WE, gripper, q, lambda: pick_image, lambda: bin_image, lambda: search_images)

    @cached_property
    def pick_image(self) -> LogicalCameraImage:
        return self.read_pick_image()

    @cached_property
    def bin_image(self) -> LogicalCameraImage:
        return self.read_bin_image()

    @cached_property
    def search_images(self) -> tuple[LogicalCameraImage, ...]:
        return self.read_search_images()


@dataclass(frozen=True)
class Decision:
    """What one update decides: the next control state (mode, tool path, suction),
    the record of an attempt that ended (None: none did) and the tool's tracking
    error (m) seen."""

    control: ControlState
    record: Optional[PickRecord] = None
    tracking_error: float = 0.0

    @property
    def mode(self) -> Mode:
        return self.control.mode

    @property
    def path(self) -> Path:
        """The tool path to follow (``X_WE`` by time)."""
        return self.control.path

    @property
    def vacuum(self) -> bool:
        """Suction on?"""
        return self.control.suction


#: A handler's answer: the next control state and, when an attempt ended, its record.
_Step = tuple[ControlState, Optional[PickRecord]]


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


def _go(s: ControlState, mode: Mode, t: float, **changes) -> ControlState:
    return replace(s, mode=mode, mode_start=t, **changes)


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


class _Moves:
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


class _Recovery:
    """Ends of failed attempts: a failure (the arm goes Home to retry, or gives the
    part up after its last attempt), a part lost or dropped into the bin, a full bin."""

    def __init__(
        self, config: TaskConfig, see: Perception, moves: _Moves, part_size: Callable[[str], float]
    ) -> None:
        self._config = config
        self._see = see
        self._moves = moves
        self._size = part_size

    def fail(
        self, inputs: MachineInput, s: ControlState, reason: PickFailure, *, reset_ik: bool = False
    ) -> _Step:
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
        return _go(
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
    def landed(t: float, s: ControlState, X_WP: RigidTransform) -> _Step:
        """The dropped part is seen at rest at ``X_WP`` at ``t``: its drop is recorded
        with where it landed, and the next attempt starts now (a retry after another
        failure counts from its first attempt; a drop has its own record's end)."""
        drop = s.pending_drop
        if drop is None:
            return s, None
        return replace(s, pending_drop=None, pick_start=t), replace(drop, position=position_of(X_WP))

    def lost(self, inputs: MachineInput, s: ControlState, name: str, mine: list[Sighting]) -> Optional[_Step]:
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
        return _go(
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
    ) -> _Step:
        """No slot left for part ``name``: it is given up where it lies (let go if
        held), the arm goes Home and the machine stops (Mode.BIN_FULL)."""
        t = inputs.t
        start = s.pick_start if s.part == name else t
        record = PickRecord(
            name, start, t, False, PickFailure.BIN_FULL, s.attempt, position_of(X_WP), given_up=True
        )
        path = self._moves.home(inputs, self._size(name))
        state = _go(
            s, Mode.BIN_FULL, t, part="", attempt=1, ignored=s.ignored + (name,), suction=False, path=path
        )
        return state, record


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
        self._moves = _Moves(self._planner, self._see, bin, X_W_home, wrist_home)
        self._recovery = _Recovery(config, self._see, self._moves, part_size)
        self._handlers: dict[Mode, Callable[[MachineInput, ControlState], _Step]] = {
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

    def _parts_seen(self, inputs: MachineInput, s: ControlState) -> Optional[list[Sighting]]:
        others = (inputs.bin_image, *inputs.search_images)
        return self._see.parts_seen(inputs.t, inputs.pick_image, others, inputs.bin_image, s.ignored)

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
        if desired is not None and s.mode not in (Mode.DESCEND, Mode.ATTACH):
            error = float(np.linalg.norm(desired.translation() - X_now.translation()))
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

    def _init(self, inputs: MachineInput, s: ControlState) -> _Step:
        return _go(s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t, path=hold(inputs.t, inputs.X_WE)), None

    def _wait_part(self, inputs: MachineInput, s: ControlState) -> _Step:
        """Plan a pick as soon as a part is seen at rest (same pose in two images)."""
        t = inputs.t
        seen = self._parts_seen(inputs, s)
        if seen is None:
            return s, None  # camera image missing: wait
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
            # given up as lost (see _Recovery.lost), so the spawner may replace it.
            return _note_candidate(s, *seen[0]), None
        if not reachable:
            if t - s.last_seen > self._config.detect_timeout:
                return _go(s, Mode.WAIT_PART, t, last_seen=t), PickRecord(
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

    def _plan_pick(self, inputs: MachineInput, s: ControlState, name: str, X_WP: RigidTransform) -> _Step:
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
        return _go(
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

    def _approach(self, inputs: MachineInput, s: ControlState) -> _Step:
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
        return _go(s, Mode.DESCEND, t, X_WP=X_WP, path=Path((fast, slow))), None

    def _descend(self, inputs: MachineInput, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return _go(s, Mode.ATTACH, inputs.t, suction=True), None

    def _attach(self, inputs: MachineInput, s: ControlState) -> _Step:
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
            return _go(s, Mode.TRANSFER, t, path=path), None
        if t - s.mode_start > c.attach_timeout:
            return self._recovery.fail(inputs, s, PickFailure.ATTACH_TIMEOUT)
        return s, None

    def _transfer(self, inputs: MachineInput, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return _go(s, Mode.RELEASE, inputs.t, suction=False), None

    def _release(self, inputs: MachineInput, s: ControlState) -> _Step:
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
        return _go(
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

    def _home(self, inputs: MachineInput, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return _go(s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t), None
