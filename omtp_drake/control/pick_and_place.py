"""Pick and place with differential IK: a state machine per robot.

The controller perceives parts **only through logical cameras** (the part's
pose is the camera's ``X_WC`` times the reported ``X_CM``) and its own arm's
joint encoders; it never reads ground truth. It asks :mod:`omtp_drake.control.tool_paths`
for tool paths of the suction-cup face (``<gripper>_tip``) and feeds them, as
desired poses, to Drake's ``DifferentialInverseKinematicsIntegrator``, whose
joint positions drive the arm's position servo.

Cycle (one handler per :class:`Mode`)::

    WAIT_PART -> APPROACH (above the part, tool down, yaw matched)
      -> DESCEND (straight down until the cup face meets the top face)
      -> ATTACH (suction on, wait for `attached`; timeout -> retry)
      -> TRANSFER (up by the approach height, an arc about the robot's base, down
         into the bin: one blended motion)
      -> RELEASE (suction off; the bin camera must see it inside; meanwhile the
         pick camera watches for the next part)
      -> WAIT_PART (after a failure: HOME first)

A part for which the bin has no slot left (where the arm reaches) is given up
(``bin_full``) and the controller stops in BIN_FULL: the task cannot finish.

Recovery, each recorded with its reason: suction does not attach
(``attach_timeout``); part dropped in transit (``dropped``); no part seen
(``no_part``); DiffIK cannot follow (``tracking``: DiffIK restarts from the
measured joints); part not in the bin after release (``missed_bin``). After a
failure the arm goes Home and retries, up to ``max_attempts`` per part; after the
last one (and after ``lost`` or ``dropped_into_bin``) the part is given up: its
record says so and where it lies, and the task's spawner replaces it.

The bin is where the bin camera last saw it (the scenario's pose until then):
a bin moved after a plan is found again for the next one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from enum import Enum
from typing import Any, Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.inverse_kinematics import (
    DifferentialInverseKinematicsIntegrator,
    DifferentialInverseKinematicsParameters,
)
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, State, ValueProducer
from pydrake.systems.primitives import ConstantValueSource

from omtp_drake.cell import arms
from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.tool_paths import Path, PickPlanner, SegmentKind, hold, yaw_of
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import BinConfig, RobotConfig, Scenario, TaskConfig


class Mode(Enum):
    """What the controller is doing."""

    INIT = "INIT"
    WAIT_PART = "WAIT_PART"
    APPROACH = "APPROACH"
    DESCEND = "DESCEND"
    ATTACH = "ATTACH"
    TRANSFER = "TRANSFER"
    RELEASE = "RELEASE"
    HOME = "HOME"
    #: The bin holds no more parts the arm can reach: the arm went Home and the
    #: controller stopped (the task cannot finish).
    BIN_FULL = "BIN_FULL"


@dataclass(frozen=True)
class PickRecord:
    """One pick attempt, as it ended."""

    part: str
    start: float
    end: float
    success: bool
    reason: str = ""
    attempt: int = 1
    #: Where the part was when the attempt ended, for a part given up on.
    position: Optional[tuple[float, float, float]] = None
    #: The controller will not try this part again (``lost``, ``dropped_into_bin``,
    #: or its last attempt failed): it lies where ``position`` says.
    given_up: bool = False

    @property
    def cycle_time(self) -> float:
        return self.end - self.start

    def to_dict(self) -> dict:
        return {
            "part": self.part,
            "start": self.start,
            "end": self.end,
            "success": self.success,
            "failure_reason": self.reason,
            "attempt": self.attempt,
            "cycle_time": self.cycle_time,
            "position": list(self.position) if self.position is not None else None,
            "given_up": self.given_up,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> PickRecord:
        """The record of :meth:`to_dict`."""
        position = data.get("position")
        return cls(
            part=data["part"],
            start=data["start"],
            end=data["end"],
            success=data["success"],
            reason=data["failure_reason"],
            attempt=data["attempt"],
            position=tuple(position) if position is not None else None,
            given_up=data.get("given_up", False),
        )


@dataclass(frozen=True)
class ControlState:
    """What the controller is doing now (its control state)."""

    mode: Mode = Mode.INIT
    mode_start: float = 0.0
    path: Path = Path()
    suction: bool = False
    #: The part being picked and where the camera saw it.
    part: str = ""
    X_WP: Optional[RigidTransform] = None
    pick_start: float = 0.0
    attempt: int = 1
    #: Parts placed so far (the next slot) and parts given up on.
    placed: int = 0
    ignored: tuple[str, ...] = ()
    bad_tracking_since: float = math.nan
    last_seen: float = 0.0
    #: Ask DiffIK to restart from the measured joints (one controller period).
    reset_ik: bool = False
    #: Since when the part being retried has not been seen by any camera.
    missing_since: float = math.nan
    #: The part to pick next as last seen, where and in which image; at rest when
    #: the image before agreed (to pick only parts at rest).
    candidate: str = ""
    candidate_X: Optional[RigidTransform] = None
    candidate_time: float = math.nan
    candidate_at_rest: bool = False

    def pose_at(self, t: float) -> Optional[RigidTransform]:
        """The tool's desired pose ``X_WE`` at ``t`` (None without a path)."""
        return self.path.pose_at(t)

    def __deepcopy__(self, memo: dict) -> ControlState:
        return self  # immutable: Drake clones abstract state at every update


@dataclass(frozen=True)
class PickHistory:
    """What the controller has done (reported apart from its control state)."""

    picks: tuple[PickRecord, ...] = ()
    #: Largest tool tracking error seen (m).
    worst_tracking_error: float = 0.0

    def __deepcopy__(self, memo: dict) -> PickHistory:
        return self  # immutable: Drake clones abstract state at every update


@dataclass(frozen=True)
class _Inputs:
    """What one update sees."""

    t: float
    X_now: RigidTransform
    gripper: GripperState
    #: The last wrist joint's measured angle from its home angle (rad).
    wrist: float


#: A handler's answer: the next control state and, when an attempt ended, its record.
_Step = tuple[ControlState, Optional[PickRecord]]


class PickAndPlaceController(LeafSystem):
    """The pick-and-place state machine of one robot.

    Input ports:
      - ``camera_image``: the pick camera's LogicalCameraImage.
      - ``bin_camera_image``: the bin camera's image (time NaN without one), to
        verify a place and to find the bin.
      - ``search_camera_<k>`` (``search_cameras`` of them): the other cameras'
        images, to find a part that fell out of the pick camera's view.
      - ``gripper_state``: the robot's GripperState (``enabled``, ``attached``).
      - ``robot_state``: the arm's measured [q; v].

    Output ports:
      - ``X_BE_desired`` (RigidTransform): desired pose of the cup face E in the
        arm's base frame B, for DiffIK.
      - ``use_robot_state`` (bool): ask DiffIK to restart from the measured q.
      - ``suction_command`` (vector [0 or 1]).
      - ``control`` (:class:`ControlState`), ``history`` (:class:`PickHistory`).

    State (abstract, updated at ``update_rate_hz``): the control state and the
    history. A scratch Context of the arm's model, for forward kinematics of the
    measured joints, is a cache entry (it depends on ``robot_state`` only).

    Frames: W world, B the arm's base_link, E ``<gripper>_tip`` (the cup face,
    +z out of the tool), C a camera, P a part's origin (its centre).
    """

    def __init__(
        self,
        config: TaskConfig,
        robot: RobotConfig,
        bin: BinConfig,
        control_plant: MultibodyPlant,
        part_size: Callable[[str], float],
        search_cameras: int = 0,
    ):
        super().__init__()
        config.validate()
        self._config = config
        self._robot = robot
        self._bin = bin
        self._part_size = part_size
        self._plant = control_plant
        self._tip = control_plant.GetFrameByName(f"{robot.gripper}_tip")
        self._X_WB = arms.base_pose(robot)
        self._X_BW = self._X_WB.inverse()
        self._planner = task_planner(config, robot)
        home_context = control_plant.CreateDefaultContext()
        self._q_home = np.asarray(arms.named_pose("Home", robot))
        control_plant.SetPositions(home_context, self._q_home)
        self._X_W_home = self._X_WB @ self._tip.CalcPoseInWorld(home_context)
        self.set_name(f"{robot.name}.pick_and_place")

        no_image = LogicalCameraImage(math.nan, "", RigidTransform(), ())
        self._image = self.DeclareAbstractInputPort("camera_image", AbstractValue.Make(no_image))
        self._bin_image = self.DeclareAbstractInputPort("bin_camera_image", AbstractValue.Make(no_image))
        self._search_images = [
            self.DeclareAbstractInputPort(f"search_camera_{k}", AbstractValue.Make(no_image))
            for k in range(search_cameras)
        ]
        self._gripper = self.DeclareAbstractInputPort(
            "gripper_state", AbstractValue.Make(GripperState(False, False, "", None, math.nan))
        )
        n = control_plant.num_positions()
        self._robot_state = self.DeclareVectorInputPort("robot_state", 2 * n)
        self._scratch = self.DeclareCacheEntry(
            description="arm model at the measured joints",
            value_producer=ValueProducer(
                allocate=AbstractValue.Make(control_plant.CreateDefaultContext()).Clone,
                calc=self._calc_scratch,
            ),
            prerequisites_of_calc={self.input_port_ticket(self._robot_state.get_index())},
        )
        self._control = self.DeclareAbstractState(AbstractValue.Make(ControlState()))
        self._history = self.DeclareAbstractState(AbstractValue.Make(PickHistory()))
        self._declare_output_ports()
        self.DeclarePeriodicUnrestrictedUpdateEvent(1.0 / config.update_rate_hz, 0.0, self._update)
        self._handlers: dict[Mode, Callable[[Context, _Inputs, ControlState], _Step]] = {
            Mode.INIT: self._init,
            Mode.WAIT_PART: self._wait_part,
            Mode.APPROACH: self._approach,
            Mode.DESCEND: self._descend,
            Mode.ATTACH: self._attach,
            Mode.TRANSFER: self._transfer,
            Mode.RELEASE: self._release,
            Mode.HOME: self._home,
            Mode.BIN_FULL: self._bin_full_idle,
        }

    # ---------------------------------------------------------------- outputs

    def _declare_output_ports(self) -> None:
        """The ports of the class doc's "Output ports" list."""
        control_ticket = {self.abstract_state_ticket(self._control)}
        self.DeclareAbstractOutputPort(
            "X_BE_desired",
            lambda: AbstractValue.Make(RigidTransform()),
            self._calc_pose,
            prerequisites_of_calc=control_ticket
            | {self.time_ticket(), self.input_port_ticket(self._robot_state.get_index())},
        )
        self.DeclareAbstractOutputPort(
            "use_robot_state",
            lambda: AbstractValue.Make(False),
            lambda c, out: out.set_value(self._control_state(c).reset_ik),
            prerequisites_of_calc=control_ticket,
        )
        self.DeclareVectorOutputPort(
            "suction_command",
            1,
            lambda c, out: out.SetAtIndex(0, float(self._control_state(c).suction)),
            prerequisites_of_calc=control_ticket,
        )
        self.DeclareStateOutputPort("control", self._control)
        self.DeclareStateOutputPort("history", self._history)

    def _control_state(self, context: Context) -> ControlState:
        return context.get_abstract_state(self._control).get_value()

    def _calc_scratch(self, context: Context, value: AbstractValue) -> None:
        q = self._robot_state.Eval(context)[: self._plant.num_positions()]
        self._plant.SetPositions(value.get_mutable_value(), q)

    def _fk(self, context: Context) -> RigidTransform:
        """``X_WE`` at the measured joints."""
        return self._X_WB @ self._tip.CalcPoseInWorld(self._scratch.Eval(context))

    def _calc_pose(self, context: Context, output: AbstractValue) -> None:
        X_WE = self._control_state(context).pose_at(context.get_time())
        if X_WE is None:
            X_WE = self._fk(context)
        output.set_value(self._X_BW @ X_WE)

    # ---------------------------------------------------------------- perception

    @staticmethod
    def _fresh(image: LogicalCameraImage, t: float, timeout: float) -> bool:
        return image.time <= t and t - image.time <= timeout

    def _parts_seen(
        self, context: Context, s: ControlState
    ) -> Optional[list[tuple[str, RigidTransform, float]]]:
        """(name, X_WP, image time) of the parts to pick: those in the pick camera's
        image, then those the bin camera and the search cameras see outside the bin
        (a part that missed it or fell on the way); None if the pick camera's image is
        stale."""
        t, timeout = context.get_time(), self._config.image_timeout
        image: LogicalCameraImage = self._image.Eval(context)
        if not self._fresh(image, t, timeout):
            return None
        seen = [
            (m.name, image.X_WC @ m.X_CM, image.time)
            for m in image.models
            if m.type == self._config.part_type and m.name and m.name not in s.ignored
        ]
        names = {name for name, _, _ in seen}
        X_WBin = self._bin_pose(context)
        for port in [self._bin_image, *self._search_images]:
            other: LogicalCameraImage = port.Eval(context)
            if not self._fresh(other, t, timeout):
                continue
            for m in other.models:
                if m.type != self._config.part_type or not m.name or m.name in s.ignored or m.name in names:
                    continue
                X_WP = other.X_WC @ m.X_CM
                if not self._bin.contains(X_WP.translation(), X_WBin):
                    seen.append((m.name, X_WP, other.time))
                    names.add(m.name)
        return seen

    def _reachable(self, X_WP: RigidTransform, size: float) -> bool:
        """Can the tool reach the part's top face, tool down, and the approach above it?"""
        p = X_WP.translation()
        radius = float(np.linalg.norm(p[:2] - self._X_WB.translation()[:2]))
        top = p[2] + size / 2
        return all(
            radius <= arms.tool_down_reach(self._robot, z) for z in (top, top + self._config.approach_height)
        )

    def _bin_seen(self, image: LogicalCameraImage) -> Optional[RigidTransform]:
        """``X_WBin`` where the bin camera's image shows the bin (None: not in it)."""
        for m in image.models:
            if m.name == self._bin.name:
                return image.X_WC @ m.X_CM
        return None

    def _bin_pose(self, context: Context) -> RigidTransform:
        """Where the bin is: as the bin camera last saw it, else the scenario's pose."""
        image: LogicalCameraImage = self._bin_image.Eval(context)
        if math.isfinite(image.time):
            seen = self._bin_seen(image)
            if seen is not None:
                return seen
        return self._bin.X_WB()

    def _in_bin(self, context: Context, name: str, released_at: float) -> Optional[bool]:
        """Does the bin camera see ``name`` inside the bin? None without a bin
        camera or before its first image taken ``settle_time`` after the release."""
        image: LogicalCameraImage = self._bin_image.Eval(context)
        if not math.isfinite(image.time) or image.time < released_at + self._config.settle_time - 1e-9:
            return None
        return self._pose_in_bin(image, name) is not None

    def _travel(
        self,
        context: Context,
        t: float,
        X_now: RigidTransform,
        X_goal: RigidTransform,
        size: float,
        min_height: float = -math.inf,
        **clear: Optional[float],
    ) -> Path:
        """Up, an arc, down (see PickPlanner.travel, which gets ``clear_start`` and
        ``clear_end``), at least ``min_height`` high and high enough near the bin for a
        part of edge ``size`` under the tool to clear its rim."""
        X_WBin = self._bin_pose(context)
        rim = self._planner.clearance_height(
            X_WBin, self._bin.geometry, size, [X_now.translation(), X_goal.translation()]
        )
        return self._planner.travel(t, X_now, X_goal, max(rim, min_height), **clear)

    def _travel_home(self, context: Context, inputs: _Inputs, size: float) -> Path:
        """The travel Home (turned to keep the wrist wound less than half a turn)."""
        X_home = self._planner.home_pose(self._X_W_home, inputs.X_now, inputs.wrist)
        return self._travel(context, inputs.t, inputs.X_now, X_home, size)

    # ---------------------------------------------------------------- the machine

    def _update(self, context: Context, state: State) -> None:
        s = self._control_state(context)
        history: PickHistory = context.get_abstract_state(self._history).get_value()
        q = self._robot_state.Eval(context)[: self._plant.num_positions()]
        inputs = _Inputs(
            context.get_time(), self._fk(context), self._gripper.Eval(context), q[5] - self._q_home[5]
        )
        if s.reset_ik:  # DiffIK has restarted from the measured joints by now
            s = replace(s, reset_ik=False)
        new, record, error = self._watch(context, inputs, s)
        if record is None:
            new, record = self._handlers[new.mode](context, inputs, new)
        if new is not self._control_state(context):
            state.get_mutable_abstract_state(self._control).set_value(new)
        if record is not None or error > history.worst_tracking_error:
            history = PickHistory(
                history.picks + ((record,) if record else ()), max(history.worst_tracking_error, error)
            )
            state.get_mutable_abstract_state(self._history).set_value(history)

    def _watch(
        self, context: Context, inputs: _Inputs, s: ControlState
    ) -> tuple[ControlState, Optional[PickRecord], float]:
        """The checks of every mode: DiffIK keeps up with the plan (outside the
        descent, which presses into the part), a carried part stays attached.
        Returns the state, a failure record if one ended the attempt, and the
        tracking error (m)."""
        t, X_now = inputs.t, inputs.X_now
        desired = s.pose_at(t)
        error = 0.0
        if desired is not None and s.mode not in (Mode.DESCEND, Mode.ATTACH):
            error = float(np.linalg.norm(desired.translation() - X_now.translation()))
            if error > self._config.tracking_tolerance:
                if math.isnan(s.bad_tracking_since):
                    s = replace(s, bad_tracking_since=t)
                elif t - s.bad_tracking_since > self._config.tracking_time:
                    return (
                        *self._fail(
                            context,
                            replace(s, bad_tracking_since=math.nan),
                            inputs,
                            "tracking",
                            reset_ik=True,
                        ),
                        error,
                    )
            elif not math.isnan(s.bad_tracking_since):
                s = replace(s, bad_tracking_since=math.nan)
        if s.mode is Mode.TRANSFER and not inputs.gripper.attached:
            return (*self._fail(context, s, inputs, "dropped"), error)
        return s, None, error

    @staticmethod
    def _go(s: ControlState, mode: Mode, t: float, **changes) -> ControlState:
        return replace(s, mode=mode, mode_start=t, **changes)

    def _fail(
        self, context: Context, s: ControlState, inputs: _Inputs, reason: str, *, reset_ik: bool = False
    ) -> _Step:
        """Records a failed attempt and sends the arm Home (suction off); with
        ``reset_ik`` DiffIK restarts from the measured joints first."""
        t = inputs.t
        if reason == "dropped" and s.part:  # last known: under the cup when it fell
            size = self._part_size(s.part)
            s = replace(s, X_WP=RigidTransform(inputs.X_now.translation() - [0.0, 0.0, size / 2]))
        attempt = s.attempt + 1 if s.part else 1
        ignored = s.ignored
        given_up = bool(s.part) and attempt > self._config.max_attempts
        if given_up:  # its last attempt: left where it was last known
            ignored = ignored + (s.part,)
            attempt = 1
        position = _position(s.X_WP) if given_up else None
        record = PickRecord(s.part, s.pick_start, t, False, reason, s.attempt, position, given_up)
        path = self._travel_home(context, inputs, self._part_size(s.part) if s.part else 0.0)
        return self._go(
            s,
            Mode.HOME,
            t,
            attempt=attempt,
            ignored=ignored,
            suction=False,
            part="" if attempt == 1 else s.part,
            path=path,
            reset_ik=reset_ik,
        ), record

    def _init(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        return self._go(
            s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t, path=hold(inputs.t, inputs.X_now)
        ), None

    def _wait_part(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        """Plan a pick as soon as a part is seen at rest (same pose in two images)."""
        t, c = inputs.t, self._config
        seen = self._parts_seen(context, s)
        if seen is None:
            return s, None  # camera image missing: wait
        # The part being picked again, or the one seen last: is it still somewhere?
        tracked = s.part or (s.candidate if s.candidate not in s.ignored else "")
        mine = [x for x in seen if x[0] == tracked] if tracked else []
        if tracked:
            lost = self._lost(context, s, t, tracked, mine)
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
        reachable = [x for x in seen if self._reachable(x[1], self._part_size(x[0]))]
        if not reachable and seen:
            # Only parts the arm cannot reach: watch one; once it is at rest it is
            # given up as lost (see _lost), so the spawner may replace it.
            return self._note_candidate(s, *seen[0]), None
        seen = reachable
        if not seen:
            if t - s.last_seen > c.detect_timeout:
                return self._go(s, Mode.WAIT_PART, t, last_seen=t), PickRecord("", t, t, False, "no_part", 1)
            return s, None
        name, X_WP, stamp = seen[0]
        if stamp != s.candidate_time:
            s = replace(self._note_candidate(s, name, X_WP, stamp), last_seen=t)
        if not (s.candidate == name and s.candidate_at_rest):
            return s, None
        if (
            self._planner.slot(self._bin_pose(context), self._bin.geometry, self._part_size(name), s.placed)
            is None
        ):
            return self._bin_full(context, s, inputs, name, X_WP)
        start = s.pick_start if (s.part == name and s.attempt > 1) else t
        X_above = self._planner.grasp_pose(
            X_WP, self._part_size(name), inputs.X_now, c.approach_height, inputs.wrist
        )
        # The cup is empty: it may leave and arrive on a curve (it stays above the
        # rim it starts over and above the approach height at the part).
        path = self._travel(
            context, t, inputs.X_now, X_above, self._part_size(name), clear_start=0.0, clear_end=0.0
        )
        return self._go(
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

    @staticmethod
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

    def _lost(
        self,
        context: Context,
        s: ControlState,
        t: float,
        name: str,
        mine: list[tuple[str, RigidTransform, float]],
    ) -> Optional[_Step]:
        """Part ``name`` (being picked again, or the last one seen) is given up on when
        it fell into the bin (``dropped_into_bin``: in the bin, but not by a place),
        lies out of reach, or no camera has seen it for ``lost_timeout`` s (``lost``,
        where it was last seen); the record has its position. None while it may still
        be picked."""
        last = s.X_WP if s.part else s.candidate_X
        in_bin = self._seen_in_bin(context, name)
        if in_bin is not None:
            why, X_WP, placed = "dropped_into_bin", in_bin, s.placed + 1
        elif mine:
            at_rest = bool(s.part) or s.candidate_at_rest  # (a part seen for the first time may still roll)
            if self._reachable(mine[0][1], self._part_size(name)) or not at_rest:
                return None
            why, X_WP, placed = "lost", mine[0][1], s.placed
        elif math.isnan(s.missing_since) or t - s.missing_since < self._config.lost_timeout:
            return None
        else:
            why, X_WP, placed = "lost", last, s.placed
        start = s.pick_start if s.part else s.candidate_time
        record = PickRecord(
            name, start, t, False, why, s.attempt if s.part else 1, position=_position(X_WP), given_up=True
        )
        return self._go(
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
        ), record

    def _seen_in_bin(self, context: Context, name: str) -> Optional[RigidTransform]:
        """``X_WP`` of part ``name`` if the bin camera's fresh image shows it in the bin."""
        image: LogicalCameraImage = self._bin_image.Eval(context)
        if not self._fresh(image, context.get_time(), self._config.image_timeout):
            return None
        return self._pose_in_bin(image, name)

    def _pose_in_bin(self, image: LogicalCameraImage, name: str) -> Optional[RigidTransform]:
        """``X_WP`` of part ``name`` if ``image`` (the bin camera's) shows it inside
        the bin, where that image shows the bin."""
        X_WBin = self._bin_seen(image)
        for m in image.models:
            if m.name == name and X_WBin is not None:
                X_WP = image.X_WC @ m.X_CM
                return X_WP if self._bin.contains(X_WP.translation(), X_WBin) else None
        return None

    def _approach(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        """Above the part: look again (it may have moved since the plan), go down."""
        t, c = inputs.t, self._config
        if not s.path.done(t):
            return s, None
        X_WP = s.X_WP
        for name, X, _ in self._parts_seen(context, s) or []:
            if name == s.part:
                X_WP = X
                break
        size = self._part_size(s.part)
        X_touch = self._planner.grasp_pose(X_WP, size, inputs.X_now, -c.press_depth)
        X_near = self._planner.grasp_pose(X_WP, size, inputs.X_now, c.slow_zone)
        fast = self._planner.move(SegmentKind.LINE, t, inputs.X_now, X_near)
        slow = self._planner.move(SegmentKind.LINE, fast.t1, X_near, X_touch, c.descent_speed)
        return self._go(s, Mode.DESCEND, t, X_WP=X_WP, path=Path((fast, slow))), None

    def _descend(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return self._go(s, Mode.ATTACH, inputs.t, suction=True), None

    def _attach(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        t, c = inputs.t, self._config
        if inputs.gripper.attached and inputs.gripper.part == s.part:
            X_WBin = self._bin_pose(context)
            size = self._part_size(s.part)
            p_slot = self._planner.slot(X_WBin, self._bin.geometry, size, s.placed)
            if p_slot is None:  # the bin holds no more the arm can reach: let go of it here
                return self._bin_full(context, s, inputs, s.part, s.X_WP)
            X_drop = self._planner.drop_pose(inputs.X_now, p_slot, yaw_of(X_WBin), inputs.wrist)
            # Straight up by the approach height before any sideways motion: the
            # part clears what it lay on (the belt's rails, its neighbours).
            lift = inputs.X_now.translation()[2] + c.approach_height
            path = self._travel(
                context, t, inputs.X_now, X_drop, size, min_height=lift, clear_start=c.approach_height
            )
            return self._go(s, Mode.TRANSFER, t, path=path), None
        if t - s.mode_start > c.attach_timeout:
            return self._fail(context, s, inputs, "attach_timeout")
        return s, None

    def _transfer(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return self._go(s, Mode.RELEASE, inputs.t, suction=False), None

    def _release(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        """Suction off; once the part has settled, the bin camera decides."""
        t = inputs.t
        s = self._watch_for_next(context, s)
        if inputs.gripper.attached or t - s.mode_start < self._config.settle_time:
            return s, None
        verdict = self._in_bin(context, s.part, s.mode_start)
        if verdict is None and self._config.bin_camera:
            return s, None  # no bin image taken after the release yet: wait
        success = verdict is not False
        record = PickRecord(s.part, s.pick_start, t, success, "" if success else "missed_bin", s.attempt)
        if not success:
            return self._fail(context, s, inputs, "missed_bin")[0], record
        # Straight on to the next part (Home only after a failure).
        return self._go(
            s,
            Mode.WAIT_PART,
            t,
            part="",
            attempt=1,
            placed=s.placed + 1,
            ignored=s.ignored + (s.part,),
            last_seen=t,
            path=hold(t, inputs.X_now),
        ), record

    def _watch_for_next(self, context: Context, s: ControlState) -> ControlState:
        """Notes the next part the pick camera shows (not the one being released), so
        that WAIT_PART may plan at once if it is at rest."""
        for name, X_WP, stamp in self._parts_seen(context, s) or []:
            if name != s.part and self._reachable(X_WP, self._part_size(name)):
                return self._note_candidate(s, name, X_WP, stamp)
        return s

    def _bin_full(
        self, context: Context, s: ControlState, inputs: _Inputs, name: str, X_WP: Optional[RigidTransform]
    ) -> _Step:
        """No slot left for part ``name``: it is given up where it lies (let go if
        held), the arm goes Home and the controller stops (Mode.BIN_FULL)."""
        t = inputs.t
        start = s.pick_start if s.part == name else t
        record = PickRecord(name, start, t, False, "bin_full", s.attempt, _position(X_WP), given_up=True)
        path = self._travel_home(context, inputs, self._part_size(name))
        state = self._go(
            s, Mode.BIN_FULL, t, part="", attempt=1, ignored=s.ignored + (name,), suction=False, path=path
        )
        return state, record

    def _bin_full_idle(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        return s, None

    def _home(self, context: Context, inputs: _Inputs, s: ControlState) -> _Step:
        if not s.path.done(inputs.t):
            return s, None
        return self._go(s, Mode.WAIT_PART, inputs.t, last_seen=inputs.t), None


def _position(X_WP: Optional[RigidTransform]) -> Optional[tuple[float, float, float]]:
    """(x, y, z) of ``X_WP`` for a record (None if unknown)."""
    if X_WP is None:
        return None
    x, y, z = (float(v) for v in X_WP.translation())
    return (x, y, z)


def add_pick_and_place(
    builder: DiagramBuilder, station, config: TaskConfig
) -> tuple[PickAndPlaceController, DifferentialInverseKinematicsIntegrator]:
    """Adds the controller and DiffIK of ``config.robot`` around ``station`` (a Station
    already added to ``builder``) and connects them to its ports."""
    config.validate()
    scenario = station.scenario
    handles = station.arm(config.robot)
    robot = handles.config
    if not robot.gripper:
        raise ConfigError(f"{robot.name} has no gripper to pick with")
    plant = handles.control_plant
    search = sorted(set(station.cameras) - {config.camera, config.bin_camera})
    controller = builder.AddSystem(
        PickAndPlaceController(
            config, robot, scenario.bin(config.bin), plant, scenario.part_size, search_cameras=len(search)
        )
    )
    diffik = builder.AddSystem(_diffik(plant, robot, config.diffik_rate_hz))

    d = station.diagram
    if config.camera not in station.cameras:
        raise ConfigError(f"task.camera {config.camera!r} is not a camera of the station")
    builder.Connect(d.GetOutputPort(f"{config.camera}.image"), controller.GetInputPort("camera_image"))
    if config.bin_camera:
        builder.Connect(
            d.GetOutputPort(f"{config.bin_camera}.image"), controller.GetInputPort("bin_camera_image")
        )
    else:
        empty = builder.AddSystem(
            ConstantValueSource(AbstractValue.Make(LogicalCameraImage(math.nan, "", RigidTransform(), ())))
        )
        builder.Connect(empty.get_output_port(), controller.GetInputPort("bin_camera_image"))
    for k, camera in enumerate(search):
        builder.Connect(d.GetOutputPort(f"{camera}.image"), controller.GetInputPort(f"search_camera_{k}"))
    suction = station.suction_name(config.robot)
    builder.Connect(d.GetOutputPort(f"{suction}.state"), controller.GetInputPort("gripper_state"))
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"), controller.GetInputPort("robot_state"))
    builder.Connect(controller.GetOutputPort("X_BE_desired"), diffik.GetInputPort("X_AE_desired"))
    builder.Connect(controller.GetOutputPort("use_robot_state"), diffik.GetInputPort("use_robot_state"))
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"), diffik.GetInputPort("robot_state"))
    builder.Connect(diffik.GetOutputPort("joint_positions"), d.GetInputPort(f"{robot.name}.position"))
    builder.Connect(controller.GetOutputPort("suction_command"), d.GetInputPort(f"{suction}.command"))
    return controller, diffik


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


def _diffik(
    plant: MultibodyPlant, robot: RobotConfig, rate_hz: float
) -> DifferentialInverseKinematicsIntegrator:
    """Drake's DiffIK on the arm's model: the tip frame, the arm's joint velocity
    and position limits, joints centred on Home."""
    params = DifferentialInverseKinematicsParameters(plant.num_positions(), plant.num_velocities())
    params.set_time_step(1.0 / rate_hz)
    vmax = np.array(arms.VELOCITY_LIMITS[robot.model])
    params.set_joint_velocity_limits((-vmax, vmax))
    params.set_joint_position_limits((np.full(6, -robot.joint_limit), np.full(6, robot.joint_limit)))
    params.set_nominal_joint_position(arms.named_pose("Home", robot))
    params.set_joint_centering_gain(0.05 * np.eye(6))
    diffik = DifferentialInverseKinematicsIntegrator(
        plant, plant.world_frame(), plant.GetFrameByName(f"{robot.gripper}_tip"), 1.0 / rate_hz, params
    )
    diffik.set_name(f"{robot.name}.diffik")
    return diffik


def history_of(controller: PickAndPlaceController, root_context: Context) -> PickHistory:
    """The controller's pick history in a Context of a diagram holding it."""
    return controller.GetOutputPort("history").Eval(controller.GetMyContextFromRoot(root_context))


def control_of(controller: PickAndPlaceController, root_context: Context) -> ControlState:
    """The controller's control state in a Context of a diagram holding it."""
    return controller.GetOutputPort("control").Eval(controller.GetMyContextFromRoot(root_context))
