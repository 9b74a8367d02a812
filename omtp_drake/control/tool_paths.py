"""Tool paths: segments, their timing and the poses along them.

Pure functions of poses and settings (no Drake systems, no Context), so each
piece is tested on its own. Where the tool goes for a pick is chosen by
:mod:`omtp_drake.control.pick_policy`; this module turns those choices into
timed motions that the controller (:mod:`omtp_drake.control.pick_and_place`)
samples.

Frames (monogram notation): W world, E the tool frame being planned (the
suction-cup face ``<gripper>_tip``, +Ez out of the tool), S a segment's start pose.

Moves have a smooth trapezoidal speed profile (sin^2 ramps: velocity and
acceleration continuous, zero at both ends) under a tool speed and acceleration
limit, as a UR's linear moves have: a long move cruises at the speed limit, a
short one peaks lower.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from functools import cached_property
from typing import Optional, Union

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix


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


def progress_array(tau: np.ndarray, ramp: float = 0.25) -> np.ndarray:
    """Path progress in [0, 1] at each normalized time of ``tau``: speed ramps up as
    sin^2 over the first ``ramp`` of the time (at most a half), cruises, ramps down
    over the last ``ramp``. Velocity and acceleration are continuous and zero at
    both ends; peak speed over mean speed is ``1 / (1 - ramp)``."""
    a = ramp
    tau = np.asarray(tau, dtype=float)

    def covered(u: np.ndarray) -> np.ndarray:  # integral of sin^2(pi u / 2a) from 0 to u
        return u / 2 - a / (2 * math.pi) * np.sin(math.pi * u / a)

    distance = np.where(
        tau < a, covered(tau), np.where(tau <= 1 - a, a / 2 + (tau - a), (1 - a) - covered(1 - tau))
    )
    return distance / (1 - a)


def progress(tau: float, ramp: float = 0.25) -> float:
    """:func:`progress_array` at one normalized time."""
    return float(progress_array(np.asarray(tau), ramp))


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


def rotations_about(rotvec: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The rotations (N, 3, 3) by the angles ``s * |rotvec|`` about the axis of ``rotvec``
    (a rotation vector: axis times angle), for each of the fractions ``s`` (N): Rodrigues'
    formula ``I + sin(a) K + (1 - cos(a)) K^2`` with K the axis' cross-product matrix."""
    angle = float(np.linalg.norm(rotvec))
    if angle == 0.0:
        return np.tile(np.eye(3), (len(s), 1, 1))
    kx, ky, kz = np.asarray(rotvec, float) / angle
    K = np.array([[0.0, -kz, ky], [kz, 0.0, -kx], [-ky, kx, 0.0]])
    a = np.asarray(s, float) * angle
    return np.eye(3) + np.sin(a)[:, None, None] * K + (1.0 - np.cos(a))[:, None, None] * (K @ K)


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
    #: Fraction of the duration each speed ramp takes (see :func:`progress_array`).
    ramp: float = 0.25

    #: Precomputed for :meth:`motions`: the ends' positions, the start's rotation,
    #: the goal's rotation relative to it, and the slerp's rotation vector (LINE) or the cylindrical
    #: start and change (ARC).
    _cache: tuple = field(init=False, repr=False, compare=False, default=())

    def __post_init__(self) -> None:
        p0, p1 = self.X_start.translation().copy(), self.X_goal.translation().copy()
        R0 = self.X_start.rotation().matrix()
        R_SG_drake = self.X_start.rotation().inverse() @ self.X_goal.rotation()
        R_SG = R_SG_drake.matrix()
        shape: Union[np.ndarray, tuple[float, ...], None] = None
        if self.kind is SegmentKind.ARC:
            (r0, a0, z0, y0), (r1, a1, z1, y1) = (
                cylindrical(self.X_start, self.centre),
                cylindrical(self.X_goal, self.centre),
            )
            shape = (r0, a0, z0, y0, r1 - r0, wrap(a1 - a0), z1 - z0, wrap(y1 - y0))
        elif self.kind is SegmentKind.LINE:
            # (Drake's log map, not scipy's Rotation: importing scipy.spatial costs a process
            # ~0.6 CPU s of start-up)
            angle_axis = R_SG_drake.ToAngleAxis()
            shape = angle_axis.angle() * angle_axis.axis()  # the slerp's axis times its angle
        object.__setattr__(self, "_cache", (p0, p1, R0, R_SG, shape))

    @property
    def t1(self) -> float:
        return self.t0 + self.duration

    def motions(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """At each of the times ``t`` (N, clamped to the segment's ends): the tool's
        positions ``p_WE`` (N, 3) and its rotations relative to the start pose,
        ``R_SE`` (N, 3, 3)."""
        p0, p1, R0, R_SG, shape = self._cache
        n = len(t)
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            p, R = np.tile(p0, (n, 1)), np.tile(np.eye(3), (n, 1, 1))
        else:
            s = progress_array(np.clip((t - self.t0) / self.duration, 0.0, 1.0), self.ramp)
            if self.kind is SegmentKind.LINE:
                p = (1 - s)[:, None] * p0 + s[:, None] * p1
                R = rotations_about(shape, s)  # the slerp at s
            else:
                p, R_WE = self._arc(s)
                R = R0.T @ R_WE
        done = t >= self.t1
        p[done], R[done] = p1, R_SG
        return p, R

    def _arc(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions and tool-down rotations ``R_WE`` at the ARC's progress ``s``."""
        r0, a0, z0, y0, dr, da, dz, dy = self._cache[4]
        r, a = r0 + s * dr, a0 + s * da
        cx, cy = self.centre
        c, sn = np.cos(a + y0 + s * dy), np.sin(a + y0 + s * dy)
        R_WE = np.zeros((len(s), 3, 3))  # tool down, Ex at the yaw a + y0 + s dy
        R_WE[:, 0, 0], R_WE[:, 0, 1], R_WE[:, 1, 0], R_WE[:, 1, 1] = c, sn, sn, -c
        R_WE[:, 2, 2] = -1.0
        return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a), z0 + s * dz]), R_WE

    def pose(self, t: float) -> RigidTransform:
        """``X_WE`` at time ``t`` (clamped to the segment's ends)."""
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            return self.X_goal if t >= self.t1 else self.X_start
        p, R_SE = self.motions(np.array([t], dtype=float))
        return RigidTransform(RotationMatrix(self._cache[2] @ R_SE[0]), p[0])


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
        p, R = self.poses(np.array([t], dtype=float))
        return RigidTransform(RotationMatrix(R[0]), p[0])

    def poses(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`pose_at` at each of the times ``t`` (N, a non-empty path): ``p_WE``
        (N, 3) and ``R_WE`` (N, 3, 3), in numpy: one call for a whole path instead of
        one per DiffIK step."""
        t = np.asarray(t, dtype=float)
        if not self.blended:
            return self._consecutive_poses(t)
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

    def _consecutive_poses(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`poses` of a path whose segments follow each other."""
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

    def done(self, t: float) -> bool:
        return not self.segments or t >= self.end_time

    @cached_property
    def end_time(self) -> float:
        """When the last segment ends (-inf for an empty path); asked at every
        update of the controller, so worked out once (a path is immutable)."""
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
