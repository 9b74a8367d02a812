"""Pick and place with differential IK: a state machine per robot.

The controller perceives parts **only through logical cameras** (the part's
pose is the camera's ``X_WC`` times the reported ``X_CM``) and its own arm's
joint encoders; it never reads ground truth. It plans tool paths for the
suction-cup face (``<gripper>_tip``) and feeds them, as desired poses, to
Drake's ``DifferentialInverseKinematicsIntegrator``, whose joint positions
drive the arm's position servo.

Cycle::

    WAIT_PART -> APPROACH (above the part, tool down, yaw matched)
      -> DESCEND (straight down until the cup face meets the top face)
      -> ATTACH (suction on, wait for `attached`; timeout -> retry)
      -> LIFT -> TRANSFER (up, an arc about the robot's base, down into the bin)
      -> RELEASE (suction off; the bin camera must see it inside)
      -> WAIT_PART (after a failure: HOME first)

Recovery, each recorded with its reason: suction does not attach
(``attach_timeout``); part dropped in transit (``dropped``); no part seen
(``no_part``); DiffIK cannot follow (``tracking``); part not in the bin after
release (``missed_bin``). After a failure the arm goes Home and retries, up to
``max_attempts`` per part.

Moves have a smooth trapezoidal speed profile (sin^2 ramps: velocity and
acceleration continuous, zero at both ends), peaking at ``max_tool_speed``
(<= 1 m/s); DiffIK also bounds joint velocities to the arm's limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import (
    DifferentialInverseKinematicsIntegrator,
    DifferentialInverseKinematicsParameters,
)
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, State
from pydrake.systems.primitives import ConstantValueSource

from omtp_drake import arms
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.logical_camera import LogicalCameraImage
from omtp_drake.scenario import BinConfig, RobotConfig, TaskConfig
from omtp_drake.suction import GripperState


@dataclass(frozen=True)
class PickRecord:
    part: str
    start: float
    end: float
    success: bool
    reason: str = ""
    attempt: int = 1

    @property
    def cycle_time(self) -> float:
        return self.end - self.start

    def to_dict(self) -> dict:
        return {"part": self.part, "start": self.start, "end": self.end, "success": self.success,
                "failure_reason": self.reason, "attempt": self.attempt,
                "cycle_time": self.cycle_time}


# ----------------------------------------------------------------------------- paths


@dataclass(frozen=True)
class Segment:
    """A tool motion from ``t0`` to ``t0 + duration`` (smooth trapezoidal speed).

    kind ``line``: straight line and slerp between poses (world frame).
    kind ``arc``: about the vertical axis through ``centre``: radius, angle,
    height and yaw interpolate linearly, the tool pointing down throughout.
    kind ``hold``: stay at ``X_start``.
    """

    kind: str
    t0: float
    duration: float
    X_start: RigidTransform
    X_goal: RigidTransform
    centre: tuple[float, float] = (0.0, 0.0)

    @property
    def t1(self) -> float:
        return self.t0 + self.duration

    def pose(self, t: float) -> RigidTransform:
        if self.kind == "hold" or self.duration <= 0:
            return self.X_goal if t >= self.t0 + self.duration else self.X_start
        s = _progress(min(1.0, max(0.0, (t - self.t0) / self.duration)))
        if self.kind == "line":
            p = (1 - s) * self.X_start.translation() + s * self.X_goal.translation()
            q = self.X_start.rotation().ToQuaternion().slerp(s, self.X_goal.rotation().ToQuaternion())
            return RigidTransform(RotationMatrix(q), p)
        (r0, a0, z0, y0), (r1, a1, z1, y1) = (_cyl(self.X_start, self.centre),
                                              _cyl(self.X_goal, self.centre))
        a1 = a0 + _wrap(a1 - a0)
        y1 = y0 + _wrap(y1 - y0)
        r, a, z, yaw = (r0 + s * (r1 - r0), a0 + s * (a1 - a0), z0 + s * (z1 - z0),
                        y0 + s * (y1 - y0))
        cx, cy = self.centre
        return tool_down(np.array([cx + r * math.cos(a), cy + r * math.sin(a), z]), a + yaw)


#: Plans peak at this fraction of the speed limit: where a joint briefly hits its
#: velocity limit DiffIK falls behind and then catches up up to ~20 % faster.
_SPEED_MARGIN = 0.8

#: Fraction of a move spent speeding up (and again slowing down).
_RAMP = 0.25
#: Peak speed over mean speed of that profile.
_PEAK_OVER_MEAN = 1.0 / (1.0 - _RAMP)


def _progress(tau: float) -> float:
    """Path progress in [0, 1] at normalized time ``tau``: speed ramps up as
    sin^2 over the first quarter, cruises, ramps down over the last quarter.
    Velocity and acceleration are continuous and zero at both ends."""
    a = _RAMP

    def ramp(u: float) -> float:  # integral of sin^2(pi u / 2a) from 0 to u
        return u / 2 - a / (2 * math.pi) * math.sin(math.pi * u / a)

    if tau < a:
        distance = ramp(tau)
    elif tau <= 1 - a:
        distance = a / 2 + (tau - a)
    else:
        distance = (1 - a) - ramp(1 - tau)
    return distance / (1 - a)


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _cyl(X: RigidTransform, centre: tuple[float, float]) -> tuple[float, float, float, float]:
    """(radius, angle, height, tool yaw relative to the angle) of a tool-down pose."""
    p = X.translation()
    dx, dy = p[0] - centre[0], p[1] - centre[1]
    angle = math.atan2(dy, dx)
    x_axis = X.rotation().col(0)
    yaw = math.atan2(x_axis[1], x_axis[0])
    return math.hypot(dx, dy), angle, p[2], _wrap(yaw - angle)


def tool_down(p_WE: np.ndarray, yaw: float) -> RigidTransform:
    """The tip pose at ``p_WE`` with the tool axis (+z) pointing down, x at ``yaw``."""
    return RigidTransform(RotationMatrix.MakeZRotation(yaw) @ RotationMatrix.MakeXRotation(math.pi),
                          p_WE)


#: Peak tool angular speed (rad/s): below the UR pan joints' 2.16-3.15 rad/s,
#: since on the arcs the tool turns with the pan joint.
_MAX_TOOL_ROTATION_SPEED = 2.0


def _duration(kind: str, X0: RigidTransform, X1: RigidTransform, speed: float,
              centre: tuple[float, float], minimum: float = 0.25) -> float:
    """Duration so the peak tool speed stays under ``speed`` (and the turn rate
    under the limit)."""
    if kind == "arc":
        (r0, a0, z0, y0), (r1, a1, z1, y1) = _cyl(X0, centre), _cyl(X1, centre)
        turn = _wrap(a1 - a0)
        distance = math.sqrt((max(r0, r1) * turn) ** 2 + (r1 - r0) ** 2 + (z1 - z0) ** 2)
        angle = abs(turn + _wrap(y1 - y0))
    else:
        distance = float(np.linalg.norm(X1.translation() - X0.translation()))
        angle = (X0.rotation().inverse() @ X1.rotation()).ToAngleAxis().angle()
    return max(minimum, _PEAK_OVER_MEAN * distance / speed,
               _PEAK_OVER_MEAN * angle / _MAX_TOOL_ROTATION_SPEED)


# ----------------------------------------------------------------------------- state


@dataclass(frozen=True)
class ControllerStatus:
    """What the controller does and has done (its abstract state)."""

    mode: str = "INIT"
    mode_start: float = 0.0
    path: tuple[Segment, ...] = ()
    suction: bool = False
    part: str = ""
    X_WP: Optional[RigidTransform] = None
    pick_start: float = 0.0
    attempt: int = 1
    picks: tuple[PickRecord, ...] = ()
    ignored: tuple[str, ...] = ()
    placed: int = 0
    bad_tracking_since: float = math.nan
    last_seen: float = 0.0
    reset_ik: bool = False
    #: The part seen at the last check and where (to wait until it is at rest).
    candidate: str = ""
    candidate_X: Optional[RigidTransform] = None
    candidate_time: float = math.nan
    #: Largest tool tracking error seen (m), for reports.
    worst_tracking_error: float = 0.0

    def pose_at(self, t: float) -> Optional[RigidTransform]:
        for segment in self.path:
            if t <= segment.t1:
                return segment.pose(t)
        return self.path[-1].pose(t) if self.path else None

    def path_done(self, t: float) -> bool:
        return not self.path or t >= self.path[-1].t1


class PickAndPlaceController(LeafSystem):
    """The pick-and-place state machine of one robot.

    Input ports:
      - ``camera_image``: the pick camera's LogicalCameraImage.
      - ``bin_camera_image`` (optional): the bin camera's image, to verify a place.
      - ``gripper_state``: the robot's GripperState (``enabled``, ``attached``).
      - ``robot_state``: the arm's measured [q; v].

    Output ports:
      - ``X_BE_desired`` (RigidTransform): desired pose of the cup face E in the
        arm's base frame B, for DiffIK.
      - ``use_robot_state`` (bool): ask DiffIK to restart from the measured q.
      - ``suction_command`` (vector [0 or 1]).
      - ``status`` (ControllerStatus).

    Frames: W world, B the arm's base_link, E ``<gripper>_tip`` (the cup face,
    +z out of the tool), C a camera, P a part's origin (its centre).
    """

    def __init__(self, config: TaskConfig, robot: RobotConfig, bin: BinConfig,
                 control_plant: MultibodyPlant, *, has_bin_camera: bool):
        super().__init__()
        config.validate()
        self._config = config
        self._robot = robot
        self._bin = bin
        self._plant = control_plant
        self._plant_context = control_plant.CreateDefaultContext()  # scratch for FK only
        self._tip = control_plant.GetFrameByName(f"{robot.gripper}_tip")
        self._X_WB = arms.base_pose(robot)
        self._X_BW = self._X_WB.inverse()
        self._home = arms.named_pose("Home", robot)
        self._has_bin_camera = has_bin_camera
        self.set_name(f"{robot.name}.pick_and_place")

        self._image = self.DeclareAbstractInputPort(
            "camera_image", AbstractValue.Make(LogicalCameraImage(
                math.nan, "", RigidTransform(), ())))
        self._bin_image = self.DeclareAbstractInputPort(
            "bin_camera_image", AbstractValue.Make(LogicalCameraImage(
                math.nan, "", RigidTransform(), ())))
        self._gripper = self.DeclareAbstractInputPort(
            "gripper_state", AbstractValue.Make(GripperState(False, False, "", None, math.nan)))
        n = control_plant.num_positions()
        self._robot_state = self.DeclareVectorInputPort("robot_state", 2 * n)
        self._status = self.DeclareAbstractState(AbstractValue.Make(ControllerStatus()))
        self.DeclareAbstractOutputPort(
            "X_BE_desired", lambda: AbstractValue.Make(RigidTransform()), self._calc_pose,
            prerequisites_of_calc={self.time_ticket(), self.abstract_state_ticket(self._status),
                                   self.input_port_ticket(self._robot_state.get_index())})
        self.DeclareAbstractOutputPort(
            "use_robot_state", lambda: AbstractValue.Make(False), self._calc_reset,
            prerequisites_of_calc={self.abstract_state_ticket(self._status)})
        self.DeclareVectorOutputPort(
            "suction_command", 1, self._calc_suction,
            prerequisites_of_calc={self.abstract_state_ticket(self._status)})
        self.DeclareStateOutputPort("status", self._status)
        self.DeclarePeriodicUnrestrictedUpdateEvent(1.0 / config.update_rate_hz, 0.0, self._update)

    # ---------------------------------------------------------------- outputs

    def _fk(self, context: Context) -> RigidTransform:
        q = self._robot_state.Eval(context)[: self._plant.num_positions()]
        self._plant.SetPositions(self._plant_context, q)
        return self._X_WB @ self._tip.CalcPoseInWorld(self._plant_context)

    def _calc_pose(self, context: Context, output: AbstractValue) -> None:
        status: ControllerStatus = context.get_abstract_state(self._status).get_value()
        X_WE = status.pose_at(context.get_time())
        if X_WE is None:
            X_WE = self._fk(context)
        output.set_value(self._X_BW @ X_WE)

    def _calc_reset(self, context: Context, output: AbstractValue) -> None:
        output.set_value(context.get_abstract_state(self._status).get_value().reset_ik)

    def _calc_suction(self, context: Context, output) -> None:
        output.SetAtIndex(0, float(context.get_abstract_state(self._status).get_value().suction))

    # ---------------------------------------------------------------- perception

    def _parts_seen(self, context: Context, status: ControllerStatus
                    ) -> Optional[list[tuple[str, RigidTransform]]]:
        """Parts in the pick camera's image, world poses; None if the image is stale."""
        image: LogicalCameraImage = self._image.Eval(context)
        t = context.get_time()
        if not image.time <= t or t - image.time > self._config.image_timeout:
            return None
        return [(m.name, image.X_WC @ m.X_CM) for m in image.models
                if m.type == self._config.part_type and m.name and m.name not in status.ignored]

    def _in_bin(self, context: Context, name: str) -> Optional[bool]:
        """Does the bin camera see ``name`` inside the bin? None without a fresh image."""
        if not self._has_bin_camera:
            return None
        image: LogicalCameraImage = self._bin_image.Eval(context)
        if not image.time <= context.get_time() or \
                context.get_time() - image.time > self._config.image_timeout:
            return None
        for m in image.models:
            if m.name == name:
                return self._bin.contains((image.X_WC @ m.X_CM).translation())
        return False

    # ---------------------------------------------------------------- planning

    def _carried_yaw(self, X_now: RigidTransform, p_goal: np.ndarray) -> float:
        """The tool's world yaw at ``p_goal`` if it turns with the arm about the base
        (its yaw relative to the base-to-tool direction unchanged): no wrist unwinding."""
        centre = self._X_WB.translation()
        p_now = X_now.translation()
        x_now = X_now.rotation().col(0)
        turn = _wrap(math.atan2(p_goal[1] - centre[1], p_goal[0] - centre[0])
                     - math.atan2(p_now[1] - centre[1], p_now[0] - centre[0]))
        return math.atan2(x_now[1], x_now[0]) + turn

    def _grasp_pose(self, X_WP: RigidTransform, X_now: RigidTransform, height: float
                    ) -> RigidTransform:
        """Tool down above the part's top face, yaw matched to the part (mod 90 deg,
        the candidate nearest the carried yaw)."""
        size = self._config.part_size
        p = X_WP.translation() + np.array([0.0, 0.0, size / 2 + height])
        x_part = X_WP.rotation().col(0)
        part_yaw = math.atan2(x_part[1], x_part[0])
        ref = self._carried_yaw(X_now, p)
        yaw = part_yaw + round(_wrap(ref - part_yaw) / (math.pi / 2)) * (math.pi / 2)
        return tool_down(p, yaw)

    def _slot(self, placed: int) -> np.ndarray:
        """World position of the cup face to release the ``placed``-th part."""
        size = self._config.part_size
        X_WBin = self._bin.X_WB()
        inner, floor_top = 2 * self._bin.INNER_HALF_WIDTH, self._bin.FLOOR_TOP
        per_row = max(1, int((inner + 1e-9) // (size + 0.01))) if self._config.grid else 1
        per_layer = per_row * per_row
        layer, k = divmod(placed, per_layer)
        pitch = inner / per_row
        ix, iy = divmod(k, per_row)
        x = (ix - (per_row - 1) / 2) * pitch
        y = (iy - (per_row - 1) / 2) * pitch
        # Release just above the landing surface, but never with the cup below
        # the rim: the wrist would hit the walls. From there the part drops.
        z = max(floor_top + (layer + 1) * size + 0.02, self._bin.HEIGHT + 0.02)
        return X_WBin @ np.array([x, y, z])

    def _near_bin(self, p: np.ndarray) -> bool:
        """Is ``p`` over the bin (with a margin for the held part and the wrist)?"""
        p_B = self._bin.X_WB().inverse() @ p
        reach = 0.2 + self._config.part_size + 0.1
        return abs(p_B[0]) < reach and abs(p_B[1]) < reach

    def _travel(self, t: float, X_now: RigidTransform, X_goal: RigidTransform
                ) -> tuple[Segment, ...]:
        """Up, a level arc about the base, down: the tool never sweeps lower than
        where it starts or ends (it would drag a held part over the belt's rails),
        and never lower over the bin than a height where a held part clears the rim.
        """
        c = self._config
        z_travel = max(X_now.translation()[2], X_goal.translation()[2])
        if self._near_bin(X_now.translation()) or self._near_bin(X_goal.translation()):
            z_travel = max(z_travel, self._bin.rim_height() + c.part_size + c.transfer_clearance)
        X_up = RigidTransform(X_now.rotation(), [*X_now.translation()[:2], z_travel])
        X_over = RigidTransform(X_goal.rotation(), [*X_goal.translation()[:2], z_travel])
        path: list[Segment] = []
        for kind, X0, X1 in (("line", X_now, X_up), ("arc", X_up, X_over), ("line", X_over, X_goal)):
            if not X0.IsNearlyEqualTo(X1, 1e-6):
                path.append(self._move(kind, path[-1].t1 if path else t, X0, X1, c.max_tool_speed))
        return tuple(path) or (Segment("hold", t, 0.0, X_now, X_goal),)

    def _move(self, kind: str, t: float, X0: RigidTransform, X1: RigidTransform,
              speed: float) -> Segment:
        centre = tuple(self._X_WB.translation()[:2])
        duration = _duration(kind, X0, X1, _SPEED_MARGIN * speed, centre)
        return Segment(kind, t, duration, X0, X1, centre)

    # ---------------------------------------------------------------- the machine

    def _update(self, context: Context, state: State) -> None:
        status: ControllerStatus = context.get_abstract_state(self._status).get_value()
        new = self._step(context, status)
        if new is not status:
            state.get_mutable_abstract_state(self._status).set_value(new)

    def _go(self, status: ControllerStatus, mode: str, t: float, **changes) -> ControllerStatus:
        return replace(status, mode=mode, mode_start=t, **changes)

    def _fail(self, status: ControllerStatus, t: float, X_now: RigidTransform, reason: str
              ) -> ControllerStatus:
        """Records a failed attempt and sends the arm Home (suction off)."""
        record = PickRecord(status.part, status.pick_start, t, False, reason, status.attempt)
        attempt = status.attempt + 1 if status.part else 1
        ignored = status.ignored
        if attempt > self._config.max_attempts:
            ignored = ignored + (status.part,)
            attempt = 1
        return self._home_path(self._go(
            status, "HOME", t, picks=status.picks + (record,), attempt=attempt, ignored=ignored,
            suction=False, part="" if attempt == 1 else status.part), t, X_now)

    def _home_path(self, status: ControllerStatus, t: float, X_now: RigidTransform
                   ) -> ControllerStatus:
        self._plant.SetPositions(self._plant_context, self._home)
        X_home = self._X_WB @ self._tip.CalcPoseInWorld(self._plant_context)
        return replace(status, path=self._travel(t, X_now, X_home), reset_ik=False)

    def _step(self, context: Context, s: ControllerStatus) -> ControllerStatus:
        c = self._config
        t = context.get_time()
        X_now = self._fk(context)
        gripper = self._gripper.Eval(context)

        if s.mode == "INIT":
            return self._go(s, "WAIT_PART", t, last_seen=t, path=(
                Segment("hold", t, 0.0, X_now, X_now),))

        # DiffIK must keep up with the plan.
        desired = s.pose_at(t)
        if desired is not None and s.mode not in ("DESCEND", "ATTACH"):
            error = float(np.linalg.norm(desired.translation() - X_now.translation()))
            s = replace(s, worst_tracking_error=max(s.worst_tracking_error, error))
            if error > c.tracking_tolerance:
                if math.isnan(s.bad_tracking_since):
                    s = replace(s, bad_tracking_since=t)
                elif t - s.bad_tracking_since > c.tracking_time:
                    s = replace(s, bad_tracking_since=math.nan, reset_ik=True)
                    return self._fail(s, t, X_now, "tracking")
            elif not math.isnan(s.bad_tracking_since):
                s = replace(s, bad_tracking_since=math.nan)

        if s.mode in ("LIFT", "TRANSFER") and not gripper.attached:
            return self._fail(s, t, X_now, "dropped")

        if s.mode == "WAIT_PART":
            seen = self._parts_seen(context, s)
            if seen is None:
                return s  # camera image missing: wait
            if s.part:
                seen = [x for x in seen if x[0] == s.part] or seen
            if not seen:
                if t - s.last_seen > c.detect_timeout:
                    record = PickRecord("", t, t, False, "no_part", 1)
                    return self._go(s, "WAIT_PART", t, picks=s.picks + (record,), last_seen=t)
                return s
            name, X_WP = seen[0]
            # Plan only on a part at rest: the same pose in two successive images.
            stamp = self._image.Eval(context).time
            if stamp == s.candidate_time:
                return s
            if s.candidate != name or s.candidate_X is None or np.linalg.norm(
                    s.candidate_X.translation() - X_WP.translation()) > 0.003:
                return replace(s, candidate=name, candidate_X=X_WP, candidate_time=stamp,
                               last_seen=t)
            start = s.pick_start if (s.part == name and s.attempt > 1) else t
            X_above = self._grasp_pose(X_WP, X_now, c.approach_height)
            return self._go(s, "APPROACH", t, part=name, X_WP=X_WP, pick_start=start,
                            path=self._travel(t, X_now, X_above), last_seen=t)

        if s.mode == "APPROACH" and s.path_done(t):
            # Look again: the part may have moved (belt, rebound) since the plan.
            seen = self._parts_seen(context, s)
            X_WP = s.X_WP
            if seen:
                match = [x for x in seen if x[0] == s.part]
                if match:
                    X_WP = match[0][1]
            X_touch = self._grasp_pose(X_WP, X_now, -c.press_depth)
            X_near = self._grasp_pose(X_WP, X_now, c.slow_zone)
            fast = self._move("line", t, X_now, X_near, c.max_tool_speed)
            slow = self._move("line", fast.t1, X_near, X_touch, c.descent_speed)
            return self._go(s, "DESCEND", t, X_WP=X_WP, path=(fast, slow))

        if s.mode == "DESCEND" and s.path_done(t):
            return self._go(s, "ATTACH", t, suction=True)

        if s.mode == "ATTACH":
            if gripper.attached and gripper.part == s.part:
                X_lift = self._grasp_pose(s.X_WP, X_now, c.approach_height)
                path = (self._move("line", t, X_now, X_lift, c.max_tool_speed),)
                return self._go(s, "LIFT", t, path=path)
            if t - s.mode_start > c.attach_timeout:
                return self._fail(s, t, X_now, "attach_timeout")
            return s

        if s.mode == "LIFT" and s.path_done(t):
            p = self._slot(s.placed)
            # Square the part with the bin (tool and part axes agree mod 90 deg).
            carried = self._carried_yaw(X_now, p)
            yaw = self._bin.yaw + round(_wrap(carried - self._bin.yaw) / (math.pi / 2)) * math.pi / 2
            X_drop = tool_down(p, yaw)
            return self._go(s, "TRANSFER", t, path=self._travel(t, X_now, X_drop))

        if s.mode == "TRANSFER" and s.path_done(t):
            return self._go(s, "RELEASE", t, suction=False)

        if s.mode == "RELEASE" and not gripper.attached and t - s.mode_start >= c.settle_time:
            verdict = self._in_bin(context, s.part)
            if verdict is None and self._has_bin_camera:
                return s  # bin image missing: wait
            success = verdict is not False
            record = PickRecord(s.part, s.pick_start, t, success,
                                "" if success else "missed_bin", s.attempt)
            # Straight on to the next part (Home only after a failure).
            return self._go(s, "WAIT_PART", t, picks=s.picks + (record,), part="", attempt=1,
                            placed=s.placed + int(success), ignored=s.ignored + (s.part,),
                            last_seen=t, path=(Segment("hold", t, 0.0, X_now, X_now),))

        if s.mode == "HOME" and s.path_done(t):
            return self._go(s, "WAIT_PART", t, last_seen=t, reset_ik=False)

        return s


def add_pick_and_place(builder: DiagramBuilder, station, config: TaskConfig
                       ) -> tuple[PickAndPlaceController, DifferentialInverseKinematicsIntegrator]:
    """Adds the controller and DiffIK of ``config.robot`` around ``station`` (a Station
    already added to ``builder``) and connects them to its ports."""
    config.validate()
    handles = station.arm(config.robot)
    robot = handles.config
    if not robot.gripper:
        raise ConfigError(f"{robot.name} has no gripper to pick with")
    for camera in [config.camera] + ([config.bin_camera] if config.bin_camera else []):
        if camera not in station.cameras:
            raise UnknownNameError("camera", camera, station.cameras)
    bins = {b.name: b for b in station.scenario.bins}
    if config.bin not in bins:
        raise UnknownNameError("bin", config.bin, bins)
    plant = handles.control_plant
    controller = builder.AddSystem(PickAndPlaceController(
        config, robot, bins[config.bin], plant, has_bin_camera=bool(config.bin_camera)))

    params = DifferentialInverseKinematicsParameters(plant.num_positions(), plant.num_velocities())
    params.set_time_step(1.0 / config.diffik_rate_hz)
    vmax = np.array(arms.VELOCITY_LIMITS[robot.model])
    params.set_joint_velocity_limits((-vmax, vmax))
    params.set_joint_position_limits((np.full(6, -robot.joint_limit), np.full(6, robot.joint_limit)))
    params.set_nominal_joint_position(arms.named_pose("Home", robot))
    params.set_joint_centering_gain(0.05 * np.eye(6))
    diffik = builder.AddSystem(DifferentialInverseKinematicsIntegrator(
        plant, plant.world_frame(), plant.GetFrameByName(f"{robot.gripper}_tip"),
        1.0 / config.diffik_rate_hz, params))
    diffik.set_name(f"{robot.name}.diffik")

    d = station.diagram
    builder.Connect(d.GetOutputPort(f"{config.camera}.image"), controller.GetInputPort("camera_image"))
    if config.bin_camera:
        builder.Connect(d.GetOutputPort(f"{config.bin_camera}.image"),
                        controller.GetInputPort("bin_camera_image"))
    else:
        empty = builder.AddSystem(ConstantValueSource(AbstractValue.Make(
            LogicalCameraImage(math.nan, "", RigidTransform(), ()))))
        builder.Connect(empty.get_output_port(), controller.GetInputPort("bin_camera_image"))
    suction = station.suction_name(config.robot)
    builder.Connect(d.GetOutputPort(f"{suction}.state"), controller.GetInputPort("gripper_state"))
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"),
                    controller.GetInputPort("robot_state"))
    builder.Connect(controller.GetOutputPort("X_BE_desired"), diffik.GetInputPort("X_AE_desired"))
    builder.Connect(controller.GetOutputPort("use_robot_state"), diffik.GetInputPort("use_robot_state"))
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"), diffik.GetInputPort("robot_state"))
    builder.Connect(diffik.GetOutputPort("joint_positions"), d.GetInputPort(f"{robot.name}.position"))
    builder.Connect(controller.GetOutputPort("suction_command"), d.GetInputPort(f"{suction}.command"))
    return controller, diffik
