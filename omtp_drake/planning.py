"""Tool paths for pick and place: segments, timing, grasp poses and bin slots.

Pure functions of poses and settings (no Drake systems, no Context), so each
piece is tested on its own. The controller (:mod:`omtp_drake.pick_and_place`)
asks this module where the tool goes next and follows the answer.

Frames (monogram notation): W world, E the tool frame being planned (the
suction-cup face ``<gripper>_tip``, +Ez out of the tool), P a part (its centre),
Bin a bin's base frame, R the robot's base (the centre of its arcs).

Moves have a smooth trapezoidal speed profile (sin^2 ramps: velocity and
acceleration continuous, zero at both ends), peaking at a given tool speed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from omtp_drake.scenario import BinGeometry


class SegmentKind(Enum):
    LINE = "line"
    ARC = "arc"
    HOLD = "hold"


#: Fraction of a move spent speeding up (and again slowing down).
RAMP = 0.25
#: Peak speed over mean speed of that profile.
PEAK_OVER_MEAN = 1.0 / (1.0 - RAMP)
#: Plans peak at this fraction of the speed limit: where a joint briefly hits its
#: velocity limit DiffIK falls behind and then catches up up to ~20 % faster.
SPEED_MARGIN = 0.8
#: Peak tool angular speed (rad/s): below the UR pan joints' 2.16-3.15 rad/s,
#: since on the arcs the tool turns with the pan joint.
MAX_TOOL_ROTATION_SPEED = 2.0
#: Shortest move (s).
MIN_DURATION = 0.25


def progress(tau: float) -> float:
    """Path progress in [0, 1] at normalized time ``tau``: speed ramps up as
    sin^2 over the first quarter, cruises, ramps down over the last quarter.
    Velocity and acceleration are continuous and zero at both ends."""
    a = RAMP

    def ramp(u: float) -> float:  # integral of sin^2(pi u / 2a) from 0 to u
        return u / 2 - a / (2 * math.pi) * math.sin(math.pi * u / a)

    if tau < a:
        distance = ramp(tau)
    elif tau <= 1 - a:
        distance = a / 2 + (tau - a)
    else:
        distance = (1 - a) - ramp(1 - tau)
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

    @property
    def t1(self) -> float:
        return self.t0 + self.duration

    def pose(self, t: float) -> RigidTransform:
        """``X_WE`` at time ``t`` (clamped to the segment's ends)."""
        if self.kind is SegmentKind.HOLD or self.duration <= 0:
            return self.X_goal if t >= self.t1 else self.X_start
        s = progress(min(1.0, max(0.0, (t - self.t0) / self.duration)))
        if self.kind is SegmentKind.LINE:
            p = (1 - s) * self.X_start.translation() + s * self.X_goal.translation()
            q = self.X_start.rotation().ToQuaternion().slerp(s, self.X_goal.rotation().ToQuaternion())
            return RigidTransform(RotationMatrix(q), p)
        (r0, a0, z0, y0), (r1, a1, z1, y1) = (
            cylindrical(self.X_start, self.centre),
            cylindrical(self.X_goal, self.centre),
        )
        a1 = a0 + wrap(a1 - a0)
        y1 = y0 + wrap(y1 - y0)
        r, a, z, yaw = (r0 + s * (r1 - r0), a0 + s * (a1 - a0), z0 + s * (z1 - z0), y0 + s * (y1 - y0))
        cx, cy = self.centre
        return tool_down(np.array([cx + r * math.cos(a), cy + r * math.sin(a), z]), a + yaw)


@dataclass(frozen=True)
class Path:
    """Consecutive segments; the tool's desired pose at any time."""

    segments: tuple[Segment, ...] = ()

    def pose_at(self, t: float) -> Optional[RigidTransform]:
        """``X_WE`` at ``t``: on the segment covering it, else at the path's end
        (None for an empty path)."""
        for segment in self.segments:
            if t <= segment.t1:
                return segment.pose(t)
        return self.segments[-1].pose(t) if self.segments else None

    def done(self, t: float) -> bool:
        return not self.segments or t >= self.segments[-1].t1

    @property
    def end_time(self) -> float:
        return self.segments[-1].t1 if self.segments else -math.inf


def hold(t: float, X_WE: RigidTransform) -> Path:
    """Stay at ``X_WE`` from ``t`` on."""
    return Path((Segment(SegmentKind.HOLD, t, 0.0, X_WE, X_WE),))


def duration(
    kind: SegmentKind, X0: RigidTransform, X1: RigidTransform, speed: float, centre: tuple[float, float]
) -> float:
    """Duration so the peak tool speed stays under ``speed`` (and the turn rate
    under :data:`MAX_TOOL_ROTATION_SPEED`)."""
    if kind is SegmentKind.ARC:
        (r0, a0, z0, y0), (r1, a1, z1, y1) = cylindrical(X0, centre), cylindrical(X1, centre)
        turn = wrap(a1 - a0)
        distance = math.sqrt((max(r0, r1) * turn) ** 2 + (r1 - r0) ** 2 + (z1 - z0) ** 2)
        angle = abs(turn + wrap(y1 - y0))
    else:
        distance = float(np.linalg.norm(X1.translation() - X0.translation()))
        angle = (X0.rotation().inverse() @ X1.rotation()).ToAngleAxis().angle()
    return max(
        MIN_DURATION, PEAK_OVER_MEAN * distance / speed, PEAK_OVER_MEAN * angle / MAX_TOOL_ROTATION_SPEED
    )


@dataclass(frozen=True)
class PickPlanner:
    """Where the tool goes, for one robot filling one bin.

    Attributes:
        X_WR: the robot's base in world (the centre of its arcs).
        max_tool_speed: tool speed limit (m/s); plans peak at
            :data:`SPEED_MARGIN` of it.
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
        return Segment(
            kind, t, duration(kind, X0, X1, SPEED_MARGIN * speed, self.centre), X0, X1, self.centre
        )

    def carried_yaw(self, X_now: RigidTransform, p_goal: np.ndarray) -> float:
        """The tool's world yaw at ``p_goal`` if it turns with the arm about the base
        (its yaw relative to the base-to-tool direction unchanged): no wrist unwinding."""
        cx, cy = self.centre
        p_now = X_now.translation()
        turn = wrap(math.atan2(p_goal[1] - cy, p_goal[0] - cx) - math.atan2(p_now[1] - cy, p_now[0] - cx))
        return yaw_of(X_now) + turn

    def grasp_pose(
        self, X_WP: RigidTransform, size: float, X_now: RigidTransform, height: float
    ) -> RigidTransform:
        """Tool down ``height`` above the top face of a cube of edge ``size`` at
        ``X_WP``, yaw matched to the part (mod 90 deg, the candidate nearest the
        carried yaw)."""
        p = X_WP.translation() + np.array([0.0, 0.0, size / 2 + height])
        part_yaw = yaw_of(X_WP)
        ref = self.carried_yaw(X_now, p)
        yaw = part_yaw + round(wrap(ref - part_yaw) / (math.pi / 2)) * (math.pi / 2)
        return tool_down(p, yaw)

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

    def drop_pose(self, X_now: RigidTransform, p_slot: np.ndarray, bin_yaw: float) -> RigidTransform:
        """The tool pose at a slot: part squared with the bin (tool and part axes
        agree mod 90 deg), the turn nearest the carried yaw."""
        carried = self.carried_yaw(X_now, p_slot)
        yaw = bin_yaw + round(wrap(carried - bin_yaw) / (math.pi / 2)) * math.pi / 2
        return tool_down(p_slot, yaw)

    def travel(
        self, t: float, X_now: RigidTransform, X_goal: RigidTransform, min_height: float = -math.inf
    ) -> Path:
        """Up, a level arc about the base, down: the tool never sweeps lower than
        where it starts or ends (it would drag a held part over the belt's rails),
        nor lower than ``min_height`` (to clear a bin's rim with a held part)."""
        z_travel = max(X_now.translation()[2], X_goal.translation()[2], min_height)
        X_up = RigidTransform(X_now.rotation(), [*X_now.translation()[:2], z_travel])
        X_over = RigidTransform(X_goal.rotation(), [*X_goal.translation()[:2], z_travel])
        segments: list[Segment] = []
        for kind, X0, X1 in (
            (SegmentKind.LINE, X_now, X_up),
            (SegmentKind.ARC, X_up, X_over),
            (SegmentKind.LINE, X_over, X_goal),
        ):
            if not X0.IsNearlyEqualTo(X1, 1e-6):
                segments.append(self.move(kind, segments[-1].t1 if segments else t, X0, X1))
        return Path(tuple(segments)) if segments else hold(t, X_goal)

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
