"""Collision-aware motion planning for one arm of the cell (a MoveIt-like back end).

:class:`ArmPlanner` owns a collision model of the whole static cell (every model
:func:`~omtp_drake.cell.station.add_cell_models` adds, without parts) and answers, for
one arm of a scenario:

- ``collisions(q)``: which bodies touch (within ``margin``) at joint positions q;
- ``plan(q_start, q_goal)``: joint waypoints of a collision-free path (the straight
  joint segment when it is free, else OMPL's RRTConnect, then OMPL's simplifier),
  deterministic for a given seed;
- ``ik(X_WE)``: joint positions putting a tool frame E at a world pose;
- ``cartesian_path(q_start, waypoints)``: a straight-line tool motion, like
  MoveIt's ``compute_cartesian_path`` (joint path and the fraction achieved);
- ``time_parameterize(path)``: a rest-to-rest joint trajectory within the arm's
  velocity and acceleration limits (TOPP-RA), as a Drake ``PiecewisePolynomial``.

It is the one facade over the package's parts, one module per concept:

- :mod:`~omtp_drake.control.motion.collision`: the collision model (Drake's
  ``SceneGraphCollisionChecker`` over the cell, self collisions);
- :mod:`~omtp_drake.control.motion.scene`: the planning scene, what is added to it
  (obstacle boxes, a held part);
- :mod:`~omtp_drake.control.motion.ik`: forward and inverse kinematics with seeds;
- :mod:`~omtp_drake.control.motion.planner_kinematics`: the planner's kinematic queries
  (``forward_kinematics``, ``ik``, ``cartesian_path``), a base class of ArmPlanner;
- :mod:`~omtp_drake.control.motion.search`: OMPL's RRTConnect and simplifier;
- :mod:`~omtp_drake.control.motion.cartesian`: straight-line tool motions;
- :mod:`~omtp_drake.control.motion.timing`: TOPP-RA time parameterization.

Building a planner and planning a blocked move take a noticeable fraction of a
second; a free move, IK and timing take milliseconds (the first timing imports
TOPP-RA and scipy). Figures: bench/README.md, "Measured".

Notation: ``X_AB`` is the pose of frame B in frame A (W world, B the arm's base,
E the tool frame, C the gripper's cup body, P a held part, O an obstacle);
``q`` are the arm's six joint positions (pan, lift, elbow, wrist 1..3).

Example::

    planner = ArmPlanner(load_scenario("lecture6_assignment4"), "robot2")
    path = planner.plan(arms.named_pose("R2Home"), arms.named_pose("R2Place"))
    trajectory = planner.time_parameterize(path)      # PiecewisePolynomial
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.control.motion.collision import CollisionModel, OtherPositions
from omtp_drake.control.motion.formatting import fmt_pairs, fmt_q
from omtp_drake.control.motion.ik import ArmKinematics
from omtp_drake.control.motion.planner_kinematics import ArmKinematicsQueries
from omtp_drake.control.motion.scene import PlanningScene
from omtp_drake.control.motion.search import JointSearch, move_out
from omtp_drake.control.motion.timing import ACCELERATION_LIMITS, scaled_limits, time_parameterize
from omtp_drake.errors import ConfigError, PlanningError, UnknownNameError
from omtp_drake.scenario import RobotConfig, Scenario, require_scenario

#: Joint-space distance (rad) between two checked configurations of an edge.
DEFAULT_EDGE_STEP = 0.01


def _check_planner_options(margin: float, edge_step: float, search_step: float, planner_range: float) -> None:
    """Raises ConfigError unless :class:`ArmPlanner`'s numeric options are in range."""
    if not 0 <= margin < 0.2:
        raise ConfigError(f"margin must be in [0, 0.2) m, got {margin}")
    if not 0 < edge_step <= 0.1:
        raise ConfigError(f"edge_step must be in (0, 0.1] rad, got {edge_step}")
    if not 0 < search_step <= 0.2 or planner_range <= 0:
        raise ConfigError(
            f"search_step must be in (0, 0.2] rad and planner_range > 0 rad, "
            f"got {search_step}, {planner_range}"
        )


class ArmPlanner(ArmKinematicsQueries):
    """Collision checking, planning, IK and time parameterization for one arm.

    Args:
        scenario: a :class:`Scenario`, or a scenario name or path.
        robot: the arm's name in the scenario (``robot1``...).
        margin: clearance (m) every robot body keeps to everything else.
        edge_step: joint-space distance (rad) between two checked configurations
            of a straight joint segment (0.01 rad moves a point 1 m out by 1 cm):
            every path :meth:`plan` returns is checked at this step.
        search_step: the coarser step at which RRTConnect checks its motions (its
            result is then checked at ``edge_step``): 3x fewer checks.
        planner_range: RRTConnect's longest extension (rad).
        self_collisions: also check the arm against itself (see
            :mod:`~omtp_drake.control.motion.collision`).

    Joint positions given to it are checked by
    :func:`~omtp_drake.cell.arms.check_joint_positions` (ConfigError: not six finite
    numbers within the arm's joint limits).

    The build takes about 0.25 s (the cell's models and the checker). One planner
    serves one thread at a time.
    """

    def __init__(
        self,
        scenario: Scenario,
        robot: str,
        *,
        margin: float = 0.01,
        edge_step: float = DEFAULT_EDGE_STEP,
        search_step: float = 0.03,
        planner_range: float = 1.0,
        self_collisions: bool = True,
    ) -> None:
        configs = {r.name: r for r in require_scenario(scenario, "ArmPlanner").robots}
        if robot not in configs:
            raise UnknownNameError("robot", robot, configs)
        _check_planner_options(margin, edge_step, search_step, planner_range)
        self._config = configs[robot]
        self._collision = CollisionModel(
            scenario, robot, margin=margin, edge_step=edge_step, self_collisions=self_collisions
        )
        self._kinematics = ArmKinematics(scenario, self._config)
        self._search = JointSearch(
            self._collision,
            self._kinematics.lower,
            self._kinematics.upper,
            max(edge_step, search_step),
            planner_range,
        )

    # ------------------------------------------------------------------ model

    @property
    def robot(self) -> RobotConfig:
        """The planned arm's configuration."""
        return self._config

    @property
    def margin(self) -> float:
        """Clearance (m) kept between robot bodies and everything else."""
        return self._collision.margin

    @property
    def joint_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper joint position limits (rad)."""
        return self._kinematics.lower.copy(), self._kinematics.upper.copy()

    @property
    def velocity_limits(self) -> np.ndarray:
        """Joint velocity limits (rad/s) of the arm's model."""
        return arms.joint_velocity_limits(self._config)

    @property
    def acceleration_limits(self) -> np.ndarray:
        """Default joint acceleration limits (rad/s^2), see :data:`ACCELERATION_LIMITS
        <omtp_drake.control.motion.timing.ACCELERATION_LIMITS>`."""
        return np.array(ACCELERATION_LIMITS[self._config.model], dtype=float)

    # ----------------------------------------------------------- the scene

    @property
    def scene(self) -> PlanningScene:
        """What is added to the cell's collision model: world obstacles, what the gripper
        carries (``set_obstacles``, ``set_held_part``, ``set_cup_boxes``, ``clear_held_part``)."""
        return self._collision.scene

    # ----------------------------------------------------------- collisions

    def collisions(self, q, other_q: OtherPositions = None) -> list[tuple[str, str]]:
        """The body pairs (robot body, other body) closer than ``margin`` at ``q``;
        empty when ``q`` is collision free. Added boxes go by their names in :attr:`scene`."""
        full = self._collision.full(self._q(q), other_q)
        if self._collision.config_free(full):
            return []
        return self._collision.pairs(full)

    def path_collisions(self, q_start, q_goal, other_q: OtherPositions = None) -> list[tuple[str, str]]:
        """The body pairs in collision anywhere on the straight joint segment
        ``q_start`` -> ``q_goal`` (checked every ``edge_step``); empty when it is free."""
        a = self._collision.full(self._q(q_start), other_q)
        b = self._collision.full(self._q(q_goal), other_q)
        return self._collision.path_pairs(a, b)

    def filter_collisions(self, pairs: Iterable[tuple[str, str]]) -> list[tuple[str, str]]:
        """Never checks the body pairs ``pairs`` (names) again, as an SRDF's
        ``disable_collisions``; returns those involving this arm (the others are skipped)."""
        return self._collision.filter_pairs(pairs)

    # ------------------------------------------------------------- planning

    def plan(
        self,
        q_start,
        q_goal,
        *,
        other_q: OtherPositions = None,
        timeout: float = 2.0,
        seed: int = 0,
        simplify: bool = True,
    ) -> list[np.ndarray]:
        """Joint waypoints of a collision-free path from ``q_start`` to ``q_goal``.

        The straight joint segment when it is free (two waypoints); otherwise OMPL's
        RRTConnect within the joint limits (motions checked every ``search_step``), then
        OMPL's path simplifier (rope shortcutting, vertex reduction); the result is
        checked every ``edge_step`` (searched again at that step if it collides, which
        is rare). The same query and ``seed`` give the same path (OMPL's global RNG is
        re-seeded from ``seed`` for each search: not thread safe).

        A start in collision (a held part pressed into the floor) moves out of it first
        (:func:`~omtp_drake.control.motion.search.move_out`).

        Raises:
            PlanningError: the goal in collision (GoalInCollisionError), a start in
                collision with no free configuration near it (StartInCollisionError; the
                messages name the bodies), or no path found within ``timeout`` s (the
                message names the bodies blocking the straight path).
        """
        if timeout <= 0:
            raise ConfigError(f"timeout must be > 0 s, got {timeout}")
        if int(seed) != seed or seed < 0:
            raise ConfigError(f"seed must be an integer >= 0, got {seed}")
        q_start, q_goal = self._q(q_start), self._q(q_goal)
        base = self._collision.full(q_start, other_q)
        goal_full = self._collision.with_arm(base, q_goal)
        self._collision.require_free("goal", q_goal, goal_full)
        if not self._collision.config_free(base):
            q_free = move_out(self._collision, q_start, base, self._kinematics, seed)
            return [q_start] + self.plan(
                q_free, q_goal, other_q=other_q, timeout=timeout, seed=seed, simplify=simplify
            )
        if self._collision.edge_free(base, goal_full):
            return [q_start, q_goal]
        path = self._search.find(q_start, q_goal, base, timeout, int(seed), simplify)
        if path is None:
            raise PlanningError(
                f"no collision-free path for {self._config.name} from {fmt_q(q_start)} to "
                f"{fmt_q(q_goal)} found within {timeout:g} s; the straight path is blocked by "
                f"{fmt_pairs(self._collision.path_pairs(base, goal_full))}"
            )
        return path

    # ---------------------------------------------------------------- timing

    def time_parameterize(
        self,
        path: Sequence[np.ndarray],
        *,
        velocity_scale: float = 1.0,
        acceleration_scale: float = 1.0,
        acceleration_limits: Sequence[float] | None = None,
        velocity_limits: Sequence[float] | None = None,
        start_time: float = 0.0,
        turn_tolerance: float = 0.002,
    ) -> PiecewisePolynomial:
        """A rest-to-rest joint trajectory along ``path`` (joint waypoints) with TOPP-RA.

        Joint velocities stay within ``velocity_scale`` times the arm's velocity limits
        and accelerations within ``acceleration_scale`` times ``acceleration_limits``
        (default :data:`~omtp_drake.control.motion.timing.ACCELERATION_LIMITS`; the
        velocity limits default to :attr:`velocity_limits`), exactly
        (the returned cubic pieces are checked and, if needed, slowed). The arm stops at
        every waypoint where its path turns so that a smooth curve through it would leave
        the straight segments by more than ``turn_tolerance`` (rad, about the shorter
        segment times the turn angle): so a planned path's collision-checked segments are
        followed exactly. Elsewhere (a Cartesian path's dense waypoints) it follows a
        cubic spline through the waypoints without stopping.

        Returns:
            A ``PiecewisePolynomial`` of the six joint positions, from ``start_time``, at
            rest at both ends; ``value(end_time())`` is the last waypoint.
        """
        vlim, alim = scaled_limits(
            self.velocity_limits if velocity_limits is None else np.asarray(velocity_limits, dtype=float),
            self.acceleration_limits if acceleration_limits is None else acceleration_limits,
            velocity_scale,
            acceleration_scale,
        )
        points = [self._q(q) for q in path]
        if not points:
            raise ConfigError("path needs at least one waypoint")
        return time_parameterize(points, vlim, alim, start_time=start_time, turn_tolerance=turn_tolerance)
