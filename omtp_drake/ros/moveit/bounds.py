"""MoveIt's joint-bounds rules, as move_group applies them to a plan's start and goal.

- The start (MoveIt's ``FixStartStateBounds`` planning request adapter): a joint
  outside its bounds by at most ``start_state_max_bounds_error`` is taken as on the
  bound ("Starting state is just outside bounds ... Assuming within bounds."); the
  plan is made from there and begins with the actual start (MoveIt's prefix
  waypoint, reached after ``min(start_state_max_dt, the plan's average segment
  duration)``). Farther out, MoveIt warns and OMPL refuses the start:
  ``START_STATE_INVALID``. The course's ``omtp_moveit_config`` sets the bounds
  error to 0.1 rad (``ompl_planning_pipeline.launch.xml``; MoveIt's own default,
  when unset, is 0.05); ``start_state_max_dt`` is MoveIt's 0.5 s.
- A joint goal (MoveIt's ``JointConstraint``): beyond a bound by more than its
  tolerance it is moved onto the bound ("... Assuming maximum bounds instead.");
  within its tolerance of a bound, the goal is sampled within the bounds: here the
  in-bounds value nearest the goal (the planner is deterministic). A negative
  tolerance is refused (``INVALID_GOAL_CONSTRAINTS``).
- A commander's joint target (``set_joint_value_target``) is accepted within
  ``goal_joint_tolerance`` (1e-4 rad) of the bounds, as MoveIt's
  ``satisfiesBounds(group, tolerance)``.

Every fix is logged with MoveIt's words and listed in the run's report
(``bounds_fixed``).
"""

from __future__ import annotations

import copy
import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.errors import PlanningError
from omtp_drake.ros.comm._core import Plan

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session

_log = logging.getLogger("moveit_commander")

#: The course's ``start_state_max_bounds_error`` (rad), ``omtp_moveit_config``'s launch file.
START_STATE_MAX_BOUNDS_ERROR = 0.1
#: MoveIt's ``start_state_max_dt`` (s): the longest time to reach the fixed start.
START_STATE_MAX_DT = 0.5
#: MoveGroupInterface's default ``goal_joint_tolerance`` (rad).
GOAL_JOINT_TOLERANCE = 1e-4


class StartStateInvalid(PlanningError):
    """A start state outside its bounds by more than the bounds error (START_STATE_INVALID)."""


@dataclass(frozen=True)
class JointBounds:
    """One arm's joint names and their position bounds (rad)."""

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray

    @classmethod
    def symmetric(cls, names: list[str], limit: float) -> JointBounds:
        n = len(names)
        return cls(tuple(names), np.full(n, -float(limit)), np.full(n, float(limit)))

    def outside(self, q: np.ndarray) -> np.ndarray:
        """How far each joint of ``q`` is outside its bounds (0 inside)."""
        return np.maximum(np.maximum(q - self.upper, self.lower - q), 0.0)

    def describe(self, i: int, q: np.ndarray) -> str:
        return f"joint '{self.names[i]}' at {q[i]:.6f} rad, bounds [{self.lower[i]:.6f}, {self.upper[i]:.6f}]"


def _note(session: Session, text: str) -> None:
    session.bounds_fixed.append(f"t={session.time:.3f} s: {text}")


def fix_start(session: Session, bounds: JointBounds, q: np.ndarray) -> np.ndarray:
    """The start to plan from: ``q`` with joints just outside their bounds put on them
    (logged and noted in the report); StartStateInvalid when one is farther out."""
    q = np.asarray(q, dtype=float)
    off = bounds.outside(q)
    far = np.flatnonzero(off > START_STATE_MAX_BOUNDS_ERROR)
    if len(far):
        i = int(far[0])
        text = (
            f"{bounds.describe(i, q)}: the starting state is outside bounds by a significant margin "
            f"(more than start_state_max_bounds_error, {START_STATE_MAX_BOUNDS_ERROR} rad)"
        )
        _log.warning("%s", text)
        raise StartStateInvalid(text)
    for i in np.flatnonzero(off > 0):
        where = bounds.describe(int(i), q)
        text = f"Starting state is just outside bounds ({where}). Assuming within bounds."
        _log.info("%s", text)
        _note(session, text)
    return np.clip(q, bounds.lower, bounds.upper)


def with_prefix(plan: Plan, q_actual: np.ndarray, q_fixed: np.ndarray) -> Plan:
    """``plan``, made from the start ``q_fixed`` that :func:`fix_start` gave for
    ``q_actual``, beginning at ``q_actual`` as MoveIt's prefix waypoint (unchanged when
    nothing was fixed)."""
    if np.array_equal(q_fixed, q_actual):
        return plan
    trajectory = plan.trajectory
    t0 = trajectory.start_time()
    q_first = trajectory.value(t0).ravel()
    segments = max(1, len(plan.path) - 1)
    dt = min(START_STATE_MAX_DT, (trajectory.end_time() - t0) / segments) or 1e-3
    zero = np.zeros((len(q_first), 2))
    prefix = PiecewisePolynomial.CubicHermite([t0, t0 + dt], np.column_stack([q_actual, q_first]), zero)
    rest = copy.deepcopy(trajectory)
    rest.shiftRight(dt)
    prefix.ConcatenateInTime(rest)
    return Plan(prefix, (np.asarray(q_actual, dtype=float), *plan.path), plan.kind, plan.fraction)


def goal_joints(session: Session, bounds: JointBounds, constraints: Any) -> dict[str, float]:
    """Joint name -> goal of MoveIt ``JointConstraint`` messages, within the bounds (see
    the module doc); ValueError for a negative tolerance."""
    index = {n: i for i, n in enumerate(bounds.names)}
    goal = {}
    for c in constraints:
        above, below = float(c.tolerance_above), float(c.tolerance_below)
        if above < 0 or below < 0:
            raise ValueError(f"JointConstraint tolerance values must be positive ({c.joint_name})")
        position = float(c.position)
        i = index.get(c.joint_name)
        if i is not None:
            lower, upper = float(bounds.lower[i]), float(bounds.upper[i])
            if position - below > upper:
                _goal_moved(session, c.joint_name, "above the maximum", upper, position)
            elif position + above < lower:
                _goal_moved(session, c.joint_name, "below the minimum", lower, position)
            position = min(max(position, lower), upper)
        goal[c.joint_name] = position
    return goal


def _goal_moved(session: Session, joint: str, side: str, bound: float, position: float) -> None:
    text = (
        f"Joint {joint} is constrained to be {side} bounds {bound:.6f} (goal {position:.6f} rad). "
        f"Assuming {side.split()[-1]} bounds instead."
    )
    _log.warning("%s", text)
    _note(session, text)


def target_within(bounds: JointBounds, values: Any) -> np.ndarray:
    """A commander's joint target ``values``: joints within ``goal_joint_tolerance`` of
    their bounds put on them (farther ones are left for the target check to refuse);
    TypeError or ValueError when they are no numbers."""
    q = np.asarray(values, dtype=float).reshape(-1)
    if q.shape != bounds.lower.shape:
        return q
    near = bounds.outside(q) <= GOAL_JOINT_TOLERANCE
    return np.where(near, np.clip(q, bounds.lower, bounds.upper), q)
