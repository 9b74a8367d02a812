"""The search for a collision-free joint path: OMPL's RRTConnect, then OMPL's path
simplifier (rope shortcutting, vertex reduction), with motions checked by Drake's
collision checker (:class:`~omtp_drake.control.motion.collision.CollisionModel`).

Deterministic for a given seed: OMPL's global RNG is re-seeded from it for each
search (not thread safe).
"""

from __future__ import annotations

import contextlib
import itertools
import logging
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou
from pydrake.common import Parallelism
from pydrake.planning import SceneGraphCollisionChecker

from omtp_drake.control.motion.collision import CollisionModel
from omtp_drake.control.motion.formatting import fmt_pairs, fmt_q
from omtp_drake.control.motion.ik import ArmKinematics
from omtp_drake.errors import PlanningError, StartInCollisionError

_log = logging.getLogger(__name__)


@contextlib.contextmanager
def _ompl_quiet() -> Iterator[None]:
    """OMPL prints to stdout (Info: lines, and an Error: line on every re-seed):
    switch its output off while we call it."""
    ou.noOutputHandler()
    try:
        yield
    finally:
        ou.restorePreviousOutputHandler()


@dataclass(frozen=True)
class _Query:
    """One search: from ``q_start`` to ``q_goal`` (the arm's joints), ``base`` the full
    configuration of everything but the arm, within ``timeout`` s, OMPL seeded from
    ``seed``, the path simplified or not."""

    q_start: np.ndarray
    q_goal: np.ndarray
    base: np.ndarray
    timeout: float
    seed: int
    simplify: bool


class _DrakeMotionValidator(ob.MotionValidator):
    """OMPL motion validator: one call to Drake's (C++) edge check per motion."""

    def __init__(
        self,
        si: ob.SpaceInformation,
        checker: SceneGraphCollisionChecker,
        to_full: Callable[[ob.State], np.ndarray],
    ) -> None:
        super().__init__(si)
        self._checker = checker
        self._to_full = to_full

    def checkMotion(self, s1, s2) -> bool:
        return self._checker.CheckEdgeCollisionFree(self._to_full(s1), self._to_full(s2))


class JointSearch:
    """RRTConnect for the planned arm of ``collision`` within joint limits.

    Args:
        collision: the collision model.
        lower, upper: the joint position limits (rad).
        search_step: the step (rad) at which RRTConnect checks its motions (its
            result is then checked at the model's ``edge_step``).
        planner_range: RRTConnect's longest extension (rad).
    """

    def __init__(
        self,
        collision: CollisionModel,
        lower: np.ndarray,
        upper: np.ndarray,
        search_step: float,
        planner_range: float,
    ) -> None:
        self._collision = collision
        self._lower, self._upper = lower, upper
        self._search_step = search_step
        self._planner_range = planner_range

    def find(
        self,
        q_start: np.ndarray,
        q_goal: np.ndarray,
        base: np.ndarray,
        timeout: float,
        seed: int,
        simplify: bool,
    ) -> list[np.ndarray] | None:
        """OMPL's RRTConnect (+ simplification) with edges checked every
        ``search_step``; the result is then checked every ``edge_step`` and, if that
        finds a collision the coarse search missed, searched again at ``edge_step``.
        None when no path is found within ``timeout`` s (``base``: the full
        configuration of everything but the arm)."""
        checker = self._collision.checker
        fine = checker.edge_step_size()
        steps = [self._search_step, fine] if self._search_step > fine else [fine]
        query = _Query(q_start, q_goal, base, timeout, seed, simplify)
        for step in steps:
            path = self._ompl_path(query, step)
            if path is None:
                return None
            edges = [
                (self._collision.with_arm(base, a), self._collision.with_arm(base, b))
                for a, b in itertools.pairwise(path)
            ]
            if all(checker.CheckEdgesCollisionFree(edges, Parallelism(1))):
                _log.debug("RRTConnect: %d waypoints (edges checked every %g rad)", len(path), step)
                return path
            _log.debug("RRTConnect path at %g rad collides at %g rad: searching again", step, fine)
        raise PlanningError(
            f"OMPL returned a path from {fmt_q(q_start)} to {fmt_q(q_goal)} with a "
            f"segment in collision (a bug: please report it)"
        )

    def _ompl_path(self, query: _Query, step: float) -> list[np.ndarray] | None:
        """One OMPL search for ``query`` with motions checked every ``step`` rad."""
        q_start, q_goal, base = query.q_start, query.q_goal, query.base
        n = len(q_start)
        checker = self._collision.checker
        fine = checker.edge_step_size()

        def to_full(state) -> np.ndarray:
            return self._collision.with_arm(base, [state[i] for i in range(n)])

        checker.set_edge_step_size(step)
        try:
            with _ompl_quiet():
                # OMPL ignores seed 0; every RNG created after this call is seeded from it.
                ou.RNG.setSeed(query.seed + 1)
                # (the validator, a Python subclass, must outlive the search)
                setup, validator = self._setup(n, to_full)
                space = setup.getStateSpace()
                start, goal = space.allocState(), space.allocState()
                for i in range(n):
                    start[i], goal[i] = float(q_start[i]), float(q_goal[i])
                setup.setStartAndGoalStates(start, goal)
                setup.solve(float(query.timeout))
                if not setup.haveExactSolutionPath():
                    return None
                solution = setup.getSolutionPath()
                if query.simplify:
                    # Not time-limited (so deterministic): shortcut, drop vertices.
                    simplifier = setup.getPathSimplifier()
                    simplifier.ropeShortcutPath(solution)
                    simplifier.reduceVertices(solution)
                path = [np.array([s[i] for i in range(n)]) for s in solution.getStates()]
        finally:
            checker.set_edge_step_size(fine)
        path[0], path[-1] = q_start.copy(), q_goal.copy()
        return path

    def _setup(
        self, n: int, to_full: Callable[[ob.State], np.ndarray]
    ) -> tuple[og.SimpleSetup, _DrakeMotionValidator]:
        """OMPL's problem (the joint box, Drake's state and motion checks, RRTConnect)
        and its motion validator."""
        checker = self._collision.checker
        space = ob.RealVectorStateSpace(n)
        bounds = ob.RealVectorBounds(n)
        for i in range(n):
            bounds.setLow(i, float(self._lower[i]))
            bounds.setHigh(i, float(self._upper[i]))
        space.setBounds(bounds)
        setup = og.SimpleSetup(space)
        setup.setStateValidityChecker(lambda state: checker.CheckConfigCollisionFree(to_full(state)))
        si = setup.getSpaceInformation()
        validator = _DrakeMotionValidator(si, checker, to_full)
        si.setMotionValidator(validator)
        planner = og.RRTConnect(si)
        planner.setRange(self._planner_range)
        setup.setPlanner(planner)
        return setup, validator


def move_out(
    collision: CollisionModel, q_start: np.ndarray, base: np.ndarray, kinematics: ArmKinematics, seed: int
) -> np.ndarray:
    """A collision-free configuration near ``q_start``, which is in collision (a held
    part pressed into the floor, say; ``base``: the full configuration there): the
    first free one of seeded random nudges of growing size, up to 0.3 rad a joint, as
    MoveIt's FixStartStateCollision adapter does. The same query and seed give the
    same configuration.

    Raises:
        StartInCollisionError: no configuration within 0.3 rad a joint is free (naming the
            pairs in collision at the start).
    """
    rng = np.random.default_rng(seed)
    for radius in (0.01, 0.02, 0.05, 0.1, 0.2, 0.3):
        for _ in range(20):
            nudge = rng.uniform(-radius, radius, len(q_start))
            q = np.clip(q_start + nudge, kinematics.lower, kinematics.upper)
            if collision.config_free(collision.with_arm(base, q)):
                return q
    raise StartInCollisionError(
        f"the start configuration {fmt_q(q_start)} of {collision.config.name} is in collision "
        f"({fmt_pairs(collision.pairs(base))}) and no configuration within 0.3 rad of it is free"
    )
