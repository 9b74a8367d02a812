"""Joint trajectories as ros_controllers' JointTrajectoryController interpolates them.

A trajectory is a list of waypoints (time, positions, and optionally velocities and
accelerations). Between two waypoints each joint follows a polynomial: linear unless both
ends give velocities, cubic (position and velocity at both ends) when they do, quintic
(also accelerations) when both give accelerations, as ``QuinticSplineSegment`` (ROS 1) and
``interpolate_between_points`` (ROS 2) decide per segment. Before
the first waypoint the trajectory holds it; after the last it holds the last position
at rest.

:class:`JointSpline` is immutable (it lives in a Context's abstract state); sample it
with :meth:`JointSpline.sample`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Optional

import numpy as np


@dataclass(frozen=True)
class Waypoint:
    """A point of a trajectory at ``time`` (s, simulated): positions and, where given,
    velocities and accelerations (one per joint)."""

    time: float
    positions: tuple[float, ...]
    velocities: Optional[tuple[float, ...]] = None
    accelerations: Optional[tuple[float, ...]] = None


def _segment(t: float, a: Waypoint, b: Waypoint, order: int) -> np.ndarray:
    """Coefficients (joint, power) of the segment from ``a`` to ``b`` of ``order`` 1, 3 or 5."""
    h = b.time - a.time
    q0, q1 = np.asarray(a.positions), np.asarray(b.positions)
    n = q0.size
    if order == 1 or h <= 0:
        return np.stack([q0, (q1 - q0) / h if h > 0 else np.zeros(n)], axis=1)
    v0 = np.asarray(a.velocities if a.velocities is not None else np.zeros(n))
    v1 = np.asarray(b.velocities if b.velocities is not None else np.zeros(n))
    if order == 3:
        c2 = (3 * (q1 - q0) - (2 * v0 + v1) * h) / h**2
        c3 = (2 * (q0 - q1) + (v0 + v1) * h) / h**3
        return np.stack([q0, v0, c2, c3], axis=1)
    a0 = np.asarray(a.accelerations if a.accelerations is not None else np.zeros(n))
    a1 = np.asarray(b.accelerations if b.accelerations is not None else np.zeros(n))
    c3 = (20 * (q1 - q0) - (8 * v1 + 12 * v0) * h - (3 * a0 - a1) * h**2) / (2 * h**3)
    c4 = (30 * (q0 - q1) + (14 * v1 + 16 * v0) * h + (3 * a0 - 2 * a1) * h**2) / (2 * h**4)
    c5 = (12 * (q1 - q0) - (6 * v1 + 6 * v0) * h - (a0 - a1) * h**2) / (2 * h**5)
    return np.stack([q0, v0, a0 / 2, c3, c4, c5], axis=1)


def _order(a: Waypoint, b: Waypoint) -> int:
    if a.accelerations is not None and b.accelerations is not None:
        return 5
    if a.velocities is not None and b.velocities is not None:
        return 3
    return 1


@dataclass(frozen=True)
class JointSpline:
    """A piecewise polynomial through waypoints (see the module doc)."""

    breaks: tuple[float, ...]
    #: One (joints, order + 1) coefficient array per segment, powers of (t - start).
    coefficients: tuple[np.ndarray, ...]
    end: tuple[float, ...]

    @staticmethod
    def through(points: Sequence[Waypoint]) -> JointSpline:
        """The spline through ``points`` (times increasing). Each segment's order is its two
        points' own: both with accelerations (5), both with velocities (3), else 1."""
        segments = tuple(_segment(a.time, a, b, _order(a, b)) for a, b in zip(points, points[1:]))
        return JointSpline(tuple(p.time for p in points), segments, tuple(points[-1].positions))

    @staticmethod
    def hold(q: Sequence[float], time: float = 0.0) -> JointSpline:
        """Rest at ``q`` at all times."""
        return JointSpline((time,), (), tuple(float(x) for x in q))

    def sample(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(positions, velocities) at ``t``."""
        if not self.coefficients or t >= self.breaks[-1]:
            return np.array(self.end), np.zeros(len(self.end))
        k = max(0, int(np.searchsorted(self.breaks, t, side="right")) - 1)
        c = self.coefficients[k]
        s = max(0.0, t - self.breaks[k])
        powers = s ** np.arange(c.shape[1])
        q = c @ powers
        dpowers = np.arange(1, c.shape[1]) * s ** np.arange(c.shape[1] - 1)
        v = c[:, 1:] @ dpowers
        return q, v

    @property
    def finish(self) -> float:
        """When the last point is reached."""
        return self.breaks[-1]
