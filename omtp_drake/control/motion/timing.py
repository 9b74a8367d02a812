"""Timing a joint path: a rest-to-rest, time-optimal trajectory (TOPP-RA) within
joint velocity and acceleration limits, as a Drake ``PiecewisePolynomial``.

The first call imports TOPP-RA (scipy's interpolate, about 0.5 s; not matplotlib's pyplot:
:func:`_import_toppra`); later ones take 10-40 ms.
"""

from __future__ import annotations

import importlib
import math
import sys
import types
from collections.abc import Mapping, Sequence

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.control.motion.formatting import fmt_q
from omtp_drake.errors import ConfigError, PlanningError

#: Default joint acceleration limits (rad/s^2), pan ... wrist 3. The URDFs have
#: none; these are our choice: the big joints reach their velocity limit
#: (about 3 rad/s) in 0.75-1 s, the light wrists in 0.65 s, which the arms'
#: servo tracks closely.
ACCELERATION_LIMITS: Mapping[str, tuple[float, ...]] = {
    "ur10": (3.0, 3.0, 4.0, 5.0, 5.0, 5.0),
    "ur5": (4.0, 4.0, 4.0, 5.0, 5.0, 5.0),
}


def scaled_limits(
    velocity_limits: np.ndarray,
    acceleration_limits: Sequence[float] | np.ndarray,
    velocity_scale: float,
    acceleration_scale: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The joint velocity and acceleration limits scaled by ``velocity_scale`` and
    ``acceleration_scale`` (each in (0, 1]); ConfigError for a bad scale or limit."""
    if not 0 < velocity_scale <= 1 or not 0 < acceleration_scale <= 1:
        raise ConfigError(
            f"velocity_scale and acceleration_scale must be in (0, 1], got "
            f"{velocity_scale}, {acceleration_scale}"
        )
    alim = np.asarray(acceleration_limits, dtype=float)
    n = len(velocity_limits)
    if alim.shape != (n,) or not np.all(np.isfinite(alim)) or np.any(alim <= 0):
        raise ConfigError(f"acceleration_limits must be {n} finite numbers > 0 rad/s^2, got {alim}")
    return np.asarray(velocity_limits, dtype=float) * velocity_scale, alim * acceleration_scale


def time_parameterize(
    path: Sequence[np.ndarray],
    velocity_limits: np.ndarray,
    acceleration_limits: np.ndarray,
    *,
    start_time: float = 0.0,
    turn_tolerance: float = 0.002,
    grid_step: float = 0.01,
) -> PiecewisePolynomial:
    """Rest-to-rest, time-optimal (TOPP-RA) trajectory along joint waypoints ``path``
    within symmetric joint ``velocity_limits`` and ``acceleration_limits``.

    See :meth:`ArmPlanner.time_parameterize
    <omtp_drake.control.motion.planner.ArmPlanner.time_parameterize>`. ``grid_step`` (rad of path length) is
    the largest spacing of TOPP-RA's grid.
    """
    _import_toppra()  # (only when needed)
    import toppra.constraint

    vlim = np.asarray(velocity_limits, dtype=float)
    alim = np.asarray(acceleration_limits, dtype=float)
    points = _distinct_waypoints(path)
    if len(points) == 1:  # already there: a constant, 1 ms long
        q = points[0][:, None]
        return PiecewisePolynomial.FirstOrderHold([start_time, start_time + 1e-3], np.hstack([q, q]))

    velocity = toppra.constraint.JointVelocityConstraint(np.column_stack([-vlim, vlim]))
    acceleration = toppra.constraint.JointAccelerationConstraint(np.column_stack([-alim, alim]))
    trajectory: PiecewisePolynomial | None = None
    t0 = start_time
    for chunk in _split_at_turns(points, turn_tolerance):
        piece = _parameterize_chunk(np.array(chunk), [velocity, acceleration], vlim, alim, t0, grid_step)
        t0 = piece.end_time()
        if trajectory is None:
            trajectory = piece
        else:
            trajectory.ConcatenateInTime(piece)
    return trajectory


class _PyplotOnUse(types.ModuleType):
    """What toppra's modules hold as ``plt``: the real ``matplotlib.pyplot``, imported at
    their first use of it (toppra uses it only in its plotting methods)."""

    def __getattr__(self, name: str):
        return getattr(importlib.import_module("matplotlib.pyplot"), name)


def _import_toppra() -> None:
    """Imports toppra without importing ``matplotlib.pyplot``: its algorithm module imports
    pyplot at the top for a plotting method omtp_drake never calls, and pyplot's figure
    machinery was ~0.6 of the ~1.2 CPU s a process (a ros-run, a graded script's child)
    spent importing toppra. While toppra is imported, ``matplotlib.pyplot`` is a
    :class:`_PyplotOnUse`; then it is taken out again, so every other import of pyplot
    (before or after) gets the real module."""
    if "toppra" in sys.modules or "matplotlib.pyplot" in sys.modules:
        return
    import matplotlib  # (the package itself: ~0.1 s; an `import a.b` needs `a`)

    sys.modules["matplotlib.pyplot"] = _PyplotOnUse("matplotlib.pyplot")
    try:
        import toppra  # noqa: F401
    finally:
        if isinstance(sys.modules.get("matplotlib.pyplot"), _PyplotOnUse):
            del sys.modules["matplotlib.pyplot"]
        if isinstance(vars(matplotlib).get("pyplot"), _PyplotOnUse):
            del matplotlib.pyplot


#: Waypoints closer than this (rad) are one: TOPP-RA cannot grid a shorter path (it fails
#: below about 1e-7 rad), and the arm's arrival tolerance is 0.5 mrad.
SAME_WAYPOINT_RAD = 1e-6


def _distinct_waypoints(path: Sequence[np.ndarray]) -> list[np.ndarray]:
    """``path``'s waypoints as float arrays, without repeats (within SAME_WAYPOINT_RAD)."""
    points = [np.asarray(path[0], dtype=float)]
    for q in path[1:]:
        q = np.asarray(q, dtype=float)
        if np.linalg.norm(q - points[-1]) > SAME_WAYPOINT_RAD:
            points.append(q)
    return points


def _split_at_turns(points: list[np.ndarray], turn_tolerance: float) -> list[list[np.ndarray]]:
    """``points`` cut into chunks (sharing their end points) at the waypoints where
    the trajectory must stop."""
    # Stop at a waypoint where a spline through it would leave the polyline by
    # more than ``turn_tolerance``: about (shorter neighbour segment) x (turn angle).
    chunks, first = [], 0
    for i in range(1, len(points) - 1):
        u, v = points[i] - points[i - 1], points[i + 1] - points[i]
        nu, nv = np.linalg.norm(u), np.linalg.norm(v)
        angle = math.acos(max(-1.0, min(1.0, float(u @ v) / (nu * nv))))
        if min(nu, nv) * angle > turn_tolerance:
            chunks.append(points[first : i + 1])
            first = i
    chunks.append(points[first:])
    return chunks


def _parameterize_chunk(
    waypoints: np.ndarray,
    constraints: list,
    vlim: np.ndarray,
    alim: np.ndarray,
    t0: float,
    grid_step: float,
) -> PiecewisePolynomial:
    """Rest-to-rest TOPP-RA trajectory, starting at time ``t0``, along a spline
    through ``waypoints`` (parameterized by polyline length) under ``constraints``."""
    import toppra
    import toppra.algorithm

    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))])
    geometric = toppra.SplineInterpolator(s, waypoints, bc_type="not-a-knot")
    grid = _toppra_grid(s, grid_step)
    instance = toppra.algorithm.TOPPRA(
        constraints, geometric, gridpoints=grid, parametrizer="ParametrizeConstAccel"
    )
    _, sd, _ = instance.compute_parameterization(0.0, 0.0)
    if sd is None or not np.all(np.isfinite(sd)):
        raise PlanningError(
            f"TOPP-RA found no time parameterization of a path segment from "
            f"{fmt_q(waypoints[0])} to {fmt_q(waypoints[-1])}"
        )
    sd = np.maximum(sd, 0.0)
    ds = np.diff(grid)
    dt = 2.0 * ds / np.maximum(sd[:-1] + sd[1:], 1e-12)
    times = np.concatenate([[0.0], np.cumsum(dt)])
    q = np.array(geometric(grid))
    q[0], q[-1] = waypoints[0], waypoints[-1]
    qd = np.array(geometric(grid, 1)) * sd[:, None]
    qd[0] = qd[-1] = 0.0
    # Hermite cubics through these samples: their exact extreme velocities and
    # accelerations decide a (rare, slight) uniform slow-down.
    k = _hermite_stretch(times, q, qd, vlim, alim)
    return PiecewisePolynomial.CubicHermite(t0 + k * times, q.T, qd.T / k)


def _toppra_grid(s: np.ndarray, grid_step: float) -> np.ndarray:
    """TOPP-RA's grid on path lengths ``s``: the waypoints' and a uniform grid at
    most ``grid_step`` apart (20 to 2000 steps), without near duplicates."""
    n_uniform = int(min(2000, max(20, math.ceil(s[-1] / grid_step))))
    grid = np.unique(np.concatenate([s, np.linspace(0.0, s[-1], n_uniform + 1)]))
    grid = grid[np.concatenate([[True], np.diff(grid) > 1e-9])]
    grid[-1] = s[-1]
    return grid


def _hermite_stretch(
    times: np.ndarray, q: np.ndarray, qd: np.ndarray, vlim: np.ndarray, alim: np.ndarray
) -> float:
    """The factor k >= 1 by which to stretch time so that the cubic Hermite pieces
    through (times, q, qd) respect the limits everywhere (velocity scales by 1/k,
    acceleration by 1/k^2)."""
    h = np.diff(times)[:, None]
    p0, p1, v0, v1 = q[:-1], q[1:], qd[:-1], qd[1:]
    # v(u) = A u^2 + B u + C on u in [0, 1]; a(u) = (2 A u + B) / h.
    A = (6.0 * (p0 - p1) + 3.0 * h * (v0 + v1)) / h
    B = (6.0 * (p1 - p0) - h * (4.0 * v0 + 2.0 * v1)) / h
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.clip(np.where(np.abs(A) > 1e-12, -B / (2.0 * A), 0.0), 0.0, 1.0)
    v_peak = np.maximum(np.maximum(np.abs(v0), np.abs(v1)), np.abs(A * u * u + B * u + v0))
    a_peak = np.maximum(np.abs(B), np.abs(2.0 * A + B)) / h
    velocity_ratio = float(np.max(v_peak / vlim))
    acceleration_ratio = float(np.max(a_peak / alim))
    return max(1.0, velocity_ratio * (1 + 1e-9), math.sqrt(acceleration_ratio) * (1 + 1e-9))
