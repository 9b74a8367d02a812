"""Where the tool goes for a pick: grasp and drop poses, bin slots, travels.

The policy of one robot filling one bin, as pure functions of poses and
settings; the timed motions it returns are :mod:`omtp_drake.control.tool_paths`'
segments and paths.

Frames (monogram notation): W world, E the tool frame (the suction-cup face, +Ez
out of the tool), P a part (its centre), Bin a bin's base frame, R the robot's
base (the centre of its arcs).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from omtp_drake.control.tool_paths import (
    Path,
    Segment,
    SegmentKind,
    hold,
    progress,
    timing,
    tool_down,
    wrap,
    yaw_of,
)
from omtp_drake.scenario import BinGeometry

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
    # moved grows with tau from 0 (at most ``allowed``) to more than ``allowed``.
    return _crossing(moved, allowed, limit)


def _crossing(f: Callable[[float], float], level: float, hi: float, tol: float = 1e-12) -> float:
    """Where the increasing ``f`` (``f(0) <= level < f(hi)``) crosses ``level``, to
    ``tol`` (s), by bisection: ~40 halvings of a ramp; scipy's ``brentq`` would do in
    fewer, but importing scipy.optimize costs every run's process ~0.5 CPU s."""
    lo = 0.0
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if f(mid) > level:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)
