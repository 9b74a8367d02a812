"""Tool paths for pick and place: segments, timing, grasp poses and bin slots.

Pure functions of poses and settings (no Drake systems, no Context), so each
piece is tested on its own. The controller (:mod:`omtp_drake.control.pick_and_place`)
asks this module where the tool goes next and follows the answer.

Frames (monogram notation): W world, E the tool frame being planned (the
suction-cup face ``<gripper>_tip``, +Ez out of the tool), P a part (its centre),
Bin a bin's base frame, R the robot's base (the centre of its arcs).

Moves have a smooth trapezoidal speed profile (sin^2 ramps: velocity and
acceleration continuous, zero at both ends) under a tool speed and acceleration
limit, as a UR's linear moves have: a long move cruises at the speed limit, a
short one peaks lower.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from enum import Enum
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from omtp_drake.scenario import BinGeometry


class SegmentKind(Enum):
    LINE = "line"
    ARC = "arc"
    HOLD = "hold"


#: Peak tool acceleration (m/s^2) of a move's ramps (a sin^2 ramp's mean is 2/pi of
#: it). At 6, a 1 m/s move takes 0.26 s to reach its speed and the arms' servo
#: torques stay below the UR5's limits (see bench/README.md).
MAX_TOOL_ACCELERATION = 6.0
#: Peak tool angular speed (rad/s): below the UR pan joints' 2.16-3.15 rad/s,
#: since on the arcs the tool turns with the pan joint; and its peak angular
#: acceleration (rad/s^2).
MAX_TOOL_ROTATION_SPEED = 2.0
MAX_TOOL_ROTATION_ACCELERATION = 12.0
#: Shortest move (s).
MIN_DURATION = 0.25
#: A travel's arc starts while the rise still has this far (m) to go, and its descent
#: this far before the arc ends (the travel height is raised by as much).
BLEND_DROP = 0.03
#: A UR's last wrist joint turns the tool about its own axis: with the tool pointing
#: down, the joint angle changes by -1 rad per rad of world yaw.
WRIST_PER_YAW = -1.0
#: How far (rad) a yaw choice may wind the last wrist joint from its home angle. Its
#: limits are +-2 pi; nearest-turn choices alone drift it there over many picks, and
#: DiffIK then stalls at the limit.
WRIST_WIND_LIMIT = math.pi


def progress(tau: float, ramp: float = 0.25) -> float:
    """Path progress in [0, 1] at normalized time ``tau``: speed ramps up as
    sin^2 over the first ``ramp`` of the time (at most a half), cruises, ramps down
    over the last ``ramp``. Velocity and acceleration are continuous and zero at
    both ends; peak speed over mean speed is ``1 / (1 - ramp)``."""
    a = ramp

    def covered(u: float) -> float:  # integral of sin^2(pi u / 2a) from 0 to u
        return u / 2 - a / (2 * math.pi) * math.sin(math.pi * u / a)

    if tau < a:
        distance = covered(tau)
    elif tau <= 1 - a:
        distance = a / 2 + (tau - a)
    else:
        distance = (1 - a) - covered(1 - tau)
    return distance / (1 - a)


def progress_array(tau: np.ndarray, ramp: float = 0.25) -> np.ndarray:
    """:func:`progress` at each of ``tau`` (numpy, the same formula)."""
    a = ramp
    tau = np.asarray(tau, dtype=float)

    def covered(u: np.ndarray) -> np.ndarray:
        return u / 2 - a / (2 * math.pi) * np.sin(math.pi * u / a)

    distance = np.where(
        tau < a, covered(tau), np.where(tau <= 1 - a, a / 2 + (tau - a), (1 - a) - covered(1 - tau))
    )
    return distance / (1 - a)


def wrap(angle: float) -> float:
    """``angle`` in [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def tool_down(p_WE: np.ndarray, yaw: float = 0.0) -> RigidTransform:
    """``X_WE`` at ``p_WE`` with the tool axis (+Ez) pointing down, Ex at ``yaw``."""
    return RigidTransform(RotationMatrix.MakeZRotation(yaw) @ RotationMatrix.MakeXRotation(math.pi), p_WE)


def yaw_of(X_WF: RigidTransform) -> float:
    """World yaw of frame F's x axis."""
    x = X_WF.rotation().col(0)
    return math.atan2(x[1], x[0])


def cylindrical(X_WE: RigidTransform, centre: tuple[float, float]) -> tuple[float, float, float, float]:
    """(radius, angle, height, tool yaw relative to the angle) of a tool-down pose
    about the vertical axis through ``centre``."""
    p = X_WE.translation()
    dx, dy = p[0] - centre[0], p[1] - centre[1]
    angle = math.atan2(dy, dx)
    return math.hypot(dx, dy), angle, p[2], wrap(yaw_of(X_WE) - angle)


@dataclass(frozen=True)
class Segment:
    """A tool motion from ``t0`` to ``t0 + duration`` (smooth trapezoidal speed).

    ``LINE``: straight line and slerp between poses (world frame).
    ``ARC``: about the vertical axis through ``centre``: radius, angle, height
    and yaw interpolate linearly, the tool pointing down throughout.
    ``HOLD``: stay at ``X_start``.
    """

    kind: SegmentKind
    t0: float
    duration: float
    X_start: RigidTransform
    X_goal: RigidTransform
    centre: tuple[float, float] = (0.0, 0.0)
    #: Fraction of the duration each speed ramp takes (see :func:`progress`).
    ramp: float = 0.25

    #: Precomputed for :meth:`motion` (numpy; evaluated 100 times a second).
    _cache: tuple = field(init=False, repr=False, compare=False, default=())

    def __post_init__(self) -> None:
        p0, p1 = self.X_start.translation().copy(), self.X_goal.translation().copy()
        R0 = self.X_start.rotation().matrix()
        if self.kind is SegmentKind.ARC:
            (r0, a0, z0, y0), (r1, a1, z1, y1) = (
                cylindrical(self.X_start, self.centre),
                cylindrical(self.X_goal, self.centre),
            )
            arc = (r0, a0, z0, y0, r1 - r0, wrap(a1 - a0), z1 - z0, wrap(y1 - y0))
            object.__setattr__(self, "_cache", (p0, p1, R0, arc))
        else:  # the slerp from R0 to R1: a turn by theta about a fixed axis (in E)
            aa = (self.X_start.rotation().inverse() @ self.X_goal.rotation()).ToAngleAxis()
            k = np.array(
                [
                    [0.0, -aa.axis()[2], aa.axis()[1]],
                    [aa.axis()[2], 0.0, -aa.axis()[0]],
                    [-aa.axis()[1], aa.axis()[0], 0.0],
                ]
            )
            object.__setattr__(self, "_cache", (p0, p1, R0, (aa.angle(), k, k @ k)))

    @functools.cached_property
    def _R_SG(self) -> np.ndarray:
        """The goal's rotation relative to the start."""
        return self._cache[2].T @ self.X_goal.rotation().matrix()

    @property
    def t1(self) -> float:
        return self.t0 + self.duration

    def motion(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(``p_WE``, ``R_SE``) at time ``t`` (clamped to the segment's ends): the
        tool's position, and its rotation relative to the start pose S."""
        p0, p1, R0, shape = self._cache
        if t >= self.t1:
            return p1, self._R_SG
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            return p0, np.eye(3)
        s = progress(min(1.0, max(0.0, (t - self.t0) / self.duration)), self.ramp)
        if self.kind is SegmentKind.LINE:
            theta, k, k2 = shape
            phi = s * theta  # Rodrigues: the slerp's turn so far
            return (1 - s) * p0 + s * p1, np.eye(3) + math.sin(phi) * k + (1 - math.cos(phi)) * k2
        r0, a0, z0, y0, dr, da, dz, dy = shape
        r, a = r0 + s * dr, a0 + s * da
        cx, cy = self.centre
        c, sn = math.cos(a + y0 + s * dy), math.sin(a + y0 + s * dy)
        R = np.array([[c, sn, 0.0], [sn, -c, 0.0], [0.0, 0.0, -1.0]])  # tool down, Ex at that yaw
        return np.array([cx + r * math.cos(a), cy + r * math.sin(a), z0 + s * dz]), R0.T @ R

    def motions(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`motion` at each of the times ``t`` (N): positions (N, 3) and
        rotations ``R_SE`` (N, 3, 3), by the same formulas in numpy."""
        p0, p1, R0, shape = self._cache
        n = len(t)
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            p, R = np.tile(p0, (n, 1)), np.tile(np.eye(3), (n, 1, 1))
        else:
            tau = np.clip((t - self.t0) / self.duration, 0.0, 1.0)
            s = progress_array(tau, self.ramp)[:, None]
            if self.kind is SegmentKind.LINE:
                theta, k, k2 = shape
                phi = s[:, :, None] * theta
                p = (1 - s) * p0 + s * p1
                R = np.eye(3) + np.sin(phi) * k + (1 - np.cos(phi)) * k2
            else:
                r0, a0, z0, y0, dr, da, dz, dy = shape
                s1 = s[:, 0]
                r, a = r0 + s1 * dr, a0 + s1 * da
                cx, cy = self.centre
                c, sn = np.cos(a + y0 + s1 * dy), np.sin(a + y0 + s1 * dy)
                R_WE = np.zeros((n, 3, 3))
                R_WE[:, 0, 0], R_WE[:, 0, 1], R_WE[:, 1, 0], R_WE[:, 1, 1] = c, sn, sn, -c
                R_WE[:, 2, 2] = -1.0
                p = np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a), z0 + s1 * dz])
                R = R0.T @ R_WE
        done = t >= self.t1
        p[done], R[done] = p1, self._R_SG
        return p, R

    def pose(self, t: float) -> RigidTransform:
        """``X_WE`` at time ``t`` (clamped to the segment's ends)."""
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            return self.X_goal if t >= self.t1 else self.X_start
        p, R_SE = self.motion(t)
        return RigidTransform(RotationMatrix(self._cache[2] @ R_SE), p)


@dataclass(frozen=True)
class Path:
    """Segments; the tool's desired pose at any time.

    Consecutive segments follow each other; ``blended`` segments may overlap in
    time, and their motions add up (each segment's displacement and turn from its
    start), so the tool goes round a corner without stopping at it.
    """

    segments: tuple[Segment, ...] = ()
    blended: bool = False

    def pose_at(self, t: float) -> Optional[RigidTransform]:
        """``X_WE`` at ``t``: on the segment covering it, else at the path's end
        (None for an empty path)."""
        if not self.segments:
            return None
        if not self.blended:
            for segment in self.segments:
                if t <= segment.t1:
                    return segment.pose(t)
            return self.segments[-1].pose(t)
        first = self.segments[0]
        p = first.X_start.translation().copy()
        R = first.X_start.rotation().matrix()
        for segment in self.segments:
            if t <= segment.t0:
                continue
            p_WE, R_SE = segment.motion(t)
            p += p_WE - segment.X_start.translation()
            R = R @ R_SE
        return RigidTransform(RotationMatrix(R), p)

    def poses(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`pose_at` at each of the times ``t`` (N, a non-empty path): ``p_WE``
        (N, 3) and ``R_WE`` (N, 3, 3), in numpy: one call for a whole path instead of
        one per DiffIK step."""
        t = np.asarray(t, dtype=float)
        if not self.blended:
            p, R = np.empty((len(t), 3)), np.empty((len(t), 3, 3))
            todo = np.ones(len(t), dtype=bool)
            for index, segment in enumerate(self.segments):
                mine = todo.copy() if index == len(self.segments) - 1 else todo & (t <= segment.t1)
                if not mine.any():
                    continue
                todo &= ~mine
                if segment.kind is SegmentKind.HOLD or segment.duration <= 0:
                    after = t[mine] >= segment.t1
                    X_goal, X_start = segment.X_goal, segment.X_start
                    p[mine] = np.where(after[:, None], X_goal.translation(), X_start.translation())
                    R[mine] = np.where(
                        after[:, None, None], X_goal.rotation().matrix(), X_start.rotation().matrix()
                    )
                else:
                    p[mine], R_SE = segment.motions(t[mine])
                    R[mine] = segment._cache[2] @ R_SE
            return p, R
        first = self.segments[0]
        p = np.tile(first.X_start.translation(), (len(t), 1))
        R = np.tile(first.X_start.rotation().matrix(), (len(t), 1, 1))
        for segment in self.segments:
            moving = t > segment.t0
            if not moving.any():
                continue
            p_WE, R_SE = segment.motions(t[moving])
            p[moving] += p_WE - segment.X_start.translation()
            R[moving] = R[moving] @ R_SE
        return p, R

    def done(self, t: float) -> bool:
        return not self.segments or t >= self.end_time

    @property
    def end_time(self) -> float:
        return max(segment.t1 for segment in self.segments) if self.segments else -math.inf


def hold(t: float, X_WE: RigidTransform) -> Path:
    """Stay at ``X_WE`` from ``t`` on."""
    return Path((Segment(SegmentKind.HOLD, t, 0.0, X_WE, X_WE),))


def timing(
    kind: SegmentKind, X0: RigidTransform, X1: RigidTransform, speed: float, centre: tuple[float, float]
) -> tuple[float, float]:
    """(duration, ramp fraction) of the quickest smooth move from ``X0`` to ``X1``:
    tool speed at most ``speed`` and acceleration at most
    :data:`MAX_TOOL_ACCELERATION`, turn rate and angular acceleration at most
    :data:`MAX_TOOL_ROTATION_SPEED` and :data:`MAX_TOOL_ROTATION_ACCELERATION`;
    never shorter than :data:`MIN_DURATION`."""
    if kind is SegmentKind.ARC:
        (r0, a0, z0, y0), (r1, a1, z1, y1) = cylindrical(X0, centre), cylindrical(X1, centre)
        turn = wrap(a1 - a0)
        distance = math.sqrt((max(r0, r1) * turn) ** 2 + (r1 - r0) ** 2 + (z1 - z0) ** 2)
        angle = abs(turn + wrap(y1 - y0))
    else:
        distance = float(np.linalg.norm(X1.translation() - X0.translation()))
        angle = (X0.rotation().inverse() @ X1.rotation()).ToAngleAxis().angle()
    # In progress units (0 to 1 over the move): the tighter of the two limits.
    rate = min(speed / max(distance, 1e-12), MAX_TOOL_ROTATION_SPEED / max(angle, 1e-12))
    accel = min(
        MAX_TOOL_ACCELERATION / max(distance, 1e-12), MAX_TOOL_ROTATION_ACCELERATION / max(angle, 1e-12)
    )
    # A sin^2 ramp to rate v over time r peaks at acceleration pi v / 2r and covers v r / 2.
    ramp_time = math.pi * rate / (2 * accel)
    if rate * ramp_time < 1.0:  # reaches the limit and cruises
        T = 1.0 / rate + ramp_time
    else:  # speeds up and slows down at once: a lower peak
        peak = math.sqrt(2 * accel / math.pi)
        ramp_time = math.pi * peak / (2 * accel)
        T = 2 * ramp_time
    if T < MIN_DURATION:  # the same shape, slower
        ramp_time *= MIN_DURATION / T
        T = MIN_DURATION
    return T, min(0.5, ramp_time / T)


@dataclass(frozen=True)
class PickPlanner:
    """Where the tool goes, for one robot filling one bin.

    Attributes:
        X_WR: the robot's base in world (the centre of its arcs).
        max_tool_speed: tool speed limit (m/s): plans peak at it (the arm's
            servo follows a plan without overshoot, :class:`arms.CommandSampler`).
        transfer_clearance: height (m) of a held part's bottom above a bin's
            rim while it moves over the bin.
        grid: place parts on a grid of slots (fill a bin) instead of all at its centre.
        reach: the largest horizontal distance (m) from the robot's base axis at
            which the tool can point down at a given world height (None: any).
    """

    X_WR: RigidTransform
    max_tool_speed: float
    transfer_clearance: float = 0.05
    grid: bool = True
    reach: Optional[Callable[[float], float]] = None

    @property
    def centre(self) -> tuple[float, float]:
        p = self.X_WR.translation()
        return float(p[0]), float(p[1])

    def move(
        self,
        kind: SegmentKind,
        t: float,
        X0: RigidTransform,
        X1: RigidTransform,
        speed: Optional[float] = None,
    ) -> Segment:
        """One segment from ``X0`` to ``X1`` starting at ``t`` (at most ``speed``)."""
        speed = self.max_tool_speed if speed is None else speed
        T, ramp = timing(kind, X0, X1, speed, self.centre)
        return Segment(kind, t, T, X0, X1, self.centre, ramp)

    def carried_yaw(self, X_now: RigidTransform, p_goal: np.ndarray) -> float:
        """The tool's world yaw at ``p_goal`` if it turns with the arm about the base
        (its yaw relative to the base-to-tool direction unchanged): no wrist unwinding."""
        cx, cy = self.centre
        p_now = X_now.translation()
        turn = wrap(math.atan2(p_goal[1] - cy, p_goal[0] - cx) - math.atan2(p_now[1] - cy, p_now[0] - cx))
        return yaw_of(X_now) + turn

    def grasp_pose(
        self,
        X_WP: RigidTransform,
        size: float,
        X_now: RigidTransform,
        height: float,
        wrist: Optional[float] = None,
    ) -> RigidTransform:
        """Tool down ``height`` above the top face of a cube of edge ``size`` at
        ``X_WP``, yaw matched to the part (mod 90 deg: see :meth:`square_yaw`; the
        last wrist joint is ``wrist`` rad from its home angle now)."""
        p = X_WP.translation() + np.array([0.0, 0.0, size / 2 + height])
        return tool_down(p, self.square_yaw(yaw_of(X_WP), self.carried_yaw(X_now, p), wrist))

    @staticmethod
    def square_yaw(yaw: float, carried: float, wrist: Optional[float] = None) -> float:
        """Of the yaws ``yaw`` + k 90 deg (a part's or a bin's square symmetry), the
        one nearest the ``carried`` yaw; with ``wrist`` (the last wrist joint's angle
        from its home angle now), the nearest that leaves the joint within
        WRIST_WIND_LIMIT of home, or if no turn under 180 deg does, the one that
        unwinds it most."""
        r = (yaw - carried) % (math.pi / 2)  # the turns (-180, 180) deg square with yaw
        turns = [r + k * math.pi / 2 for k in range(-2, 2) if abs(r + k * math.pi / 2) < math.pi - 1e-9]
        if wrist is None:
            return carried + min(turns, key=abs)
        within = [d for d in turns if abs(wrist + WRIST_PER_YAW * d) <= WRIST_WIND_LIMIT]
        if within:
            return carried + min(within, key=abs)
        return carried + min(turns, key=lambda d: abs(wrist + WRIST_PER_YAW * d))

    def slots(self, X_WBin: RigidTransform, bin_geometry: BinGeometry, size: float) -> list[np.ndarray]:
        """World positions of the cup face to release parts of edge ``size``, in
        filling order: every slot the bin holds and the arm reaches.

        Slots fill a grid per layer (with 1 cm gaps), nearest the robot's base
        first; layers stack up while a part's centre stays below the rim (the
        bin's capacity). The release is just above the landing surface, but
        never with the cup below the rim (the wrist would hit the walls); from
        there the part drops. A slot the arm cannot reach tool-down (``reach``)
        is skipped.
        """
        inner, floor_top = 2 * bin_geometry.inner_half_width, bin_geometry.floor_top
        per_row = max(1, int((inner + 1e-9) // (size + 0.01))) if self.grid else 1
        pitch = inner / per_row
        grid = [
            ((ix - (per_row - 1) / 2) * pitch, (iy - (per_row - 1) / 2) * pitch)
            for ix in range(per_row)
            for iy in range(per_row)
        ]
        centre = self.X_WR.translation()[:2]
        result = []
        layer = 0
        while floor_top + (layer + 0.5) * size <= bin_geometry.height + 1e-9:
            z = max(floor_top + (layer + 1) * size + 0.02, bin_geometry.height + 0.02)
            points = [X_WBin @ np.array([x, y, z]) for x, y in grid]
            points.sort(key=lambda p: (round(float(np.linalg.norm(p[:2] - centre)), 6), p[0], p[1]))
            result += [
                p
                for p in points
                if self.reach is None or np.linalg.norm(p[:2] - centre) <= self.reach(float(p[2]))
            ]
            layer += 1
        return result

    def slot(
        self, X_WBin: RigidTransform, bin_geometry: BinGeometry, size: float, placed: int
    ) -> Optional[np.ndarray]:
        """Where to release the ``placed``-th part (see :meth:`slots`); None when the
        bin holds no more that the arm can reach."""
        slots = self.slots(X_WBin, bin_geometry, size)
        return slots[placed] if placed < len(slots) else None

    def drop_pose(
        self, X_now: RigidTransform, p_slot: np.ndarray, bin_yaw: float, wrist: Optional[float] = None
    ) -> RigidTransform:
        """The tool pose at a slot: part squared with the bin (tool and part axes
        agree mod 90 deg; see :meth:`square_yaw`)."""
        return tool_down(p_slot, self.square_yaw(bin_yaw, self.carried_yaw(X_now, p_slot), wrist))

    def home_pose(
        self, X_home: RigidTransform, X_now: RigidTransform, wrist: Optional[float] = None
    ) -> RigidTransform:
        """``X_home`` turned about the world's z by a multiple of 90 deg (the cup is
        round: any of them waits as well; see :meth:`square_yaw`)."""
        p = X_home.translation()
        yaw = self.square_yaw(yaw_of(X_home), self.carried_yaw(X_now, p), wrist)
        return RigidTransform(RotationMatrix.MakeZRotation(yaw - yaw_of(X_home)) @ X_home.rotation(), p)

    def travel(
        self,
        t: float,
        X_now: RigidTransform,
        X_goal: RigidTransform,
        min_height: float = -math.inf,
        *,
        clear_start: Optional[float] = None,
        clear_end: Optional[float] = None,
    ) -> Path:
        """Up, a level arc about the base, down, blended into one motion: the arc
        starts before the rise ends and the descent starts before the arc ends, so
        the tool does not stop at the corners. The travel height is at least
        ``min_height`` (to clear a bin's rim with a held part) and the start and goal
        heights, raised by :data:`BLEND_DROP` when the tool goes up or down.

        The arc starts once the tool is ``clear_start`` above its start, and ends
        while it is still ``clear_end`` above the goal (or all the way up, for a
        travel that goes up less than that); by default (None) within
        ``BLEND_DROP`` of the travel height, so the tool never sweeps lower than where
        it starts or ends (a held part would drag over the belt's rails or catch a
        bin's rim). Overlaps stay within the speed ramps, so the tool never moves
        faster than the speed limit."""
        z_travel = max(X_now.translation()[2], X_goal.translation()[2], min_height)
        rise = z_travel - X_now.translation()[2]
        drop = z_travel - X_goal.translation()[2]
        if rise > BLEND_DROP or drop > BLEND_DROP:
            z_travel += BLEND_DROP
            rise, drop = rise + BLEND_DROP, drop + BLEND_DROP
        # How far each vertical line may still move while the arc does.
        blend_up = BLEND_DROP if clear_start is None else max(0.0, rise - clear_start)
        blend_down = BLEND_DROP if clear_end is None else max(0.0, drop - clear_end)
        X_up = RigidTransform(X_now.rotation(), [*X_now.translation()[:2], z_travel])
        X_over = RigidTransform(X_goal.rotation(), [*X_goal.translation()[:2], z_travel])
        segments: list[Segment] = []
        # A leg shorter than 1 um is not moved on its own, but what it would have
        # moved is not lost: the next leg starts where the last one ended, and the
        # last leg ends at the goal, so the path ends exactly at X_goal.
        X_from = X_now
        for kind, X1 in ((SegmentKind.LINE, X_up), (SegmentKind.ARC, X_over), (SegmentKind.LINE, X_goal)):
            if X_from.IsNearlyEqualTo(X1, 1e-6):
                continue
            following = self.move(kind, t, X_from, X1)
            if segments:
                previous = segments[-1]
                start = previous.t1 - _overlap(previous, following, blend_up, blend_down)
                following = replace(following, t0=start)
            segments.append(following)
            X_from = X1
        if not segments:
            return hold(t, X_goal)
        if X_from is not X_goal:  # the last leg ends within 1 um of the goal: end on it
            last = segments[-1]
            segments[-1] = replace(self.move(last.kind, t, last.X_start, X_goal), t0=last.t0)
        return Path(tuple(segments), blended=True)

    def clearance_height(
        self, X_WBin: RigidTransform, bin_geometry: BinGeometry, held_size: float, points: list[np.ndarray]
    ) -> float:
        """The lowest tool height for a travel between ``points`` near the bin:
        a held part of edge ``held_size`` clears the rim by ``transfer_clearance``;
        -inf when no point is over (or near) the bin."""
        X_BinW = X_WBin.inverse()
        reach = bin_geometry.inner_half_width + held_size + 0.1
        for p in points:
            p_B = X_BinW @ p
            if abs(p_B[0]) < reach and abs(p_B[1]) < reach:
                rim = (X_WBin @ np.array([0.0, 0.0, bin_geometry.height]))[2]
                return rim + held_size + self.transfer_clearance
        return -math.inf


def _overlap(previous: Segment, following: Segment, blend_up: float, blend_down: float) -> float:
    """How long (s) ``following`` may start before ``previous`` ends: while a rising
    line (``previous``) still has at most ``blend_up`` to go, or a descending one
    (``following``) has moved at most ``blend_down``; and within both speed ramps (a
    ramp down and a ramp up that overlap by at most the shorter one add up to at
    most the speed limit)."""
    limit = min(previous.ramp * previous.duration, following.ramp * following.duration)
    if previous.kind is SegmentKind.LINE:  # rising
        line, allowed, rising = previous, blend_up, True
    elif following.kind is SegmentKind.LINE:  # descending
        line, allowed, rising = following, blend_down, False
    else:
        return 0.0
    length = float(np.linalg.norm(line.X_goal.translation() - line.X_start.translation()))

    def moved(tau: float) -> float:
        """How far the vertical line moves in the overlap of length ``tau``."""
        if rising:
            return length * (1.0 - progress(1.0 - tau / line.duration, line.ramp))
        return length * progress(tau / line.duration, line.ramp)

    if moved(limit) <= allowed:
        return limit
    low, high = 0.0, limit
    for _ in range(30):  # the longest tau with moved(tau) <= allowed (monotonic)
        mid = 0.5 * (low + high)
        low, high = (mid, high) if moved(mid) <= allowed else (low, mid)
    return low
