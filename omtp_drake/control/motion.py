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

Collision model. Drake's ``SceneGraphCollisionChecker`` over a ``RobotDiagram`` of
the cell. The robot is the arm and its gripper; everything else (the other arm at
given joint positions, pedestals, bins, conveyor, floor) is environment. Extra
boxes (parts lying around) and a part held by the gripper are added to the
checker. A pair is in collision when its signed distance is below ``margin``.

Self collisions. The station filters every pair within one arm (the simulation
needs no self contact). The checker re-enables, for planning, the pairs at least
three joints apart (e.g. upper arm / wrist 2, forearm / gripper) and the arm's
links three or more joints away from its pedestal and base (forearm, wrists, gripper). Pairs two joints apart
stay filtered: their convex-hull collision shapes overlap at ordinary poses (the
forearm and wrist 2 hulls touch in 40 % of random configurations).

Cost (2 cores, robot 2 at bin 1, bench/bench_planning.py): build about 0.25 s;
a blocked move about 0.1-0.2 s, a free one about 10 ms; IK 3-60 ms; the first
time parameterization imports TOPP-RA (scipy, about 0.7 s), later ones 10-40 ms.

Notation: ``X_AB`` is the pose of frame B in frame A (W world, B the arm's base,
E the tool frame, C the gripper's cup body, P a held part, O an obstacle);
``q`` are the arm's six joint positions (pan, lift, elbow, wrist 1..3).

Example::

    planner = ArmPlanner("lecture6_assignment4", "robot2")
    path = planner.plan(arms.named_pose("R2Home"), arms.named_pose("R2Place"))
    trajectory = planner.time_parameterize(path)      # PiecewisePolynomial
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
from collections.abc import Iterator, Mapping, Sequence
from typing import TypeAlias

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou
from pydrake.common import Parallelism
from pydrake.geometry import Box, GeometryId, Role
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import InverseKinematics
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, ModelInstanceIndex, RigidBody
from pydrake.planning import RobotDiagramBuilder, SceneGraphCollisionChecker
from pydrake.solvers import Solve
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.cell.poses import interpolate_pose
from omtp_drake.cell.station import ArmHandles, CellModels, add_cell_models
from omtp_drake.errors import ConfigError, PlanningError, UnknownNameError
from omtp_drake.scenario import RobotConfig, Scenario, load_scenario

_log = logging.getLogger(__name__)


#: Default joint acceleration limits (rad/s^2), pan ... wrist 3. The URDFs have
#: none; these are our choice: the big joints reach their velocity limit
#: (about 3 rad/s) in 0.75-1 s, the light wrists in 0.65 s, which the arms'
#: servo tracks closely.
ACCELERATION_LIMITS: Mapping[str, tuple[float, ...]] = {
    "ur10": (3.0, 3.0, 4.0, 5.0, 5.0, 5.0),
    "ur5": (4.0, 4.0, 4.0, 5.0, 5.0, 5.0),
}

#: Joint-space distance (rad) between two checked configurations of an edge.
DEFAULT_EDGE_STEP = 0.01

#: What one obstacle is: its pose in world and its size (edge or x, y, z edges).
Obstacle = tuple[RigidTransform, float | Sequence[float]]

#: Other arms' joint positions: one array (when there is one other arm) or by robot name.
OtherPositions: TypeAlias = np.ndarray | Sequence[float] | Mapping[str, Sequence[float]] | None

#: The course's named poses (short names) that seed IK after the caller's seed.
_SEED_POSES = ("Home", "PreGrasp", "Place", "Up")

_HELD_GROUP = "held_part"
_OBSTACLE_GROUP = "obstacles"


@contextlib.contextmanager
def _ompl_quiet() -> Iterator[None]:
    """OMPL prints to stdout (Info: lines, and an Error: line on every re-seed):
    switch its output off while we call it."""
    ou.noOutputHandler()
    try:
        yield
    finally:
        ou.restorePreviousOutputHandler()


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


def _robot_instances(handles: ArmHandles) -> list[ModelInstanceIndex]:
    """The model instances the planner moves: the arm, and its gripper if it has one."""
    return [handles.arm] + ([handles.gripper] if handles.gripper is not None else [])


class _DrakeMotionValidator(ob.MotionValidator):
    """OMPL motion validator: one call to Drake's (C++) edge check per motion."""

    def __init__(self, si: ob.SpaceInformation, checker: SceneGraphCollisionChecker, to_full) -> None:
        super().__init__(si)
        self._checker = checker
        self._to_full = to_full

    def checkMotion(self, s1, s2) -> bool:
        return self._checker.CheckEdgeCollisionFree(self._to_full(s1), self._to_full(s2))


class ArmPlanner:
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
        self_collisions: also check the arm against itself (see module doc).

    The build takes about 0.25 s (the cell's models and the checker). One planner
    serves one thread at a time.
    """

    def __init__(
        self,
        scenario: Scenario | str,
        robot: str,
        *,
        margin: float = 0.01,
        edge_step: float = DEFAULT_EDGE_STEP,
        search_step: float = 0.03,
        planner_range: float = 1.0,
        self_collisions: bool = True,
    ) -> None:
        if not isinstance(scenario, Scenario):
            scenario = load_scenario(scenario)
        configs = {r.name: r for r in scenario.robots}
        if robot not in configs:
            raise UnknownNameError("robot", robot, configs)
        _check_planner_options(margin, edge_step, search_step, planner_range)
        self._config: RobotConfig = configs[robot]
        self._margin = float(margin)

        models = self._build_checker(scenario, robot, edge_step=edge_step, margin=margin)
        handles = models.arms[robot]
        plant = self._checker.plant()
        self._index_joints(plant, models, robot)
        self._find_tool_frames(plant, handles.gripper)
        self._robot_bodies = [
            plant.get_body(b) for inst in _robot_instances(handles) for b in plant.GetBodyIndices(inst)
        ]
        if self_collisions:
            self._enable_self_collisions(plant, handles.pedestal)
        self._search_step = max(edge_step, search_step)
        self._planner_range = planner_range
        self._obstacle_ids: list[GeometryId] = []
        self._held_ids: list[GeometryId] = []
        self._build_kinematics(scenario)

    def _build_checker(
        self, scenario: Scenario, robot: str, *, edge_step: float, margin: float
    ) -> CellModels:
        """Builds the collision checker over the whole cell (no parts), with ``robot``'s
        arm and gripper as the robot; returns the cell's model handles."""
        builder = RobotDiagramBuilder(time_step=0.0)
        models = add_cell_models(builder.plant(), builder.scene_graph(), scenario, parts=False)
        builder.plant().Finalize()
        self._checker = SceneGraphCollisionChecker(
            model=builder.Build(),
            robot_model_instances=_robot_instances(models.arms[robot]),
            edge_step_size=edge_step,
            env_collision_padding=margin,
            self_collision_padding=margin,
            implicit_context_parallelism=Parallelism(1),
        )
        return models

    def _index_joints(self, plant: MultibodyPlant, models: CellModels, robot: str) -> None:
        """Where each arm's joints sit in the checker's configurations, the default
        configuration (every arm at its initial pose) and the planned arm's limits."""

        def joint_indices(instance: ModelInstanceIndex, name: str) -> np.ndarray:
            return np.array(
                [plant.GetJointByName(f"{name}_{j}", instance).position_start() for j in arms.JOINT_NAMES]
            )

        self._q_index = joint_indices(models.arms[robot].arm, robot)
        self._others: dict[str, np.ndarray] = {}
        self._q_default = plant.GetPositions(plant.CreateDefaultContext())
        for name, other in models.arms.items():
            if name != robot:
                self._others[name] = joint_indices(other.arm, name)
                self._q_default[self._others[name]] = arms.named_pose(other.config.initial_pose, other.config)
        self._q_default[self._q_index] = arms.named_pose(self._config.initial_pose, self._config)
        limit = self._config.joint_limit
        self._lower = np.full(len(arms.JOINT_NAMES), -limit)
        self._upper = np.full(len(arms.JOINT_NAMES), limit)

    def _find_tool_frames(self, plant: MultibodyPlant, gripper_instance: ModelInstanceIndex | None) -> None:
        """The tool frames' names in the plant, and the gripper's cup body (if any)."""
        gripper = self._config.gripper
        self._frame_names = arms.tool_frame_names(self._config)
        if gripper:
            self._cup: RigidBody | None = plant.GetBodyByName(f"{gripper}_cup", gripper_instance)
        else:
            self._cup = None

    def _build_kinematics(self, scenario: Scenario) -> None:
        """IK and forward kinematics: the arm and gripper alone, base at the origin."""
        self._X_WB = arms.base_pose(self._config)
        self._ik_plant: MultibodyPlant = arms.make_control_plant(self._config, scenario.gravity)
        self._ik_context = self._ik_plant.CreateDefaultContext()
        robot = self._config.name
        self._ik_index = np.array(
            [self._ik_plant.GetJointByName(f"{robot}_{j}").position_start() for j in arms.JOINT_NAMES]
        )

    # ------------------------------------------------------------------ model

    @property
    def robot(self) -> RobotConfig:
        """The planned arm's configuration."""
        return self._config

    @property
    def margin(self) -> float:
        """Clearance (m) kept between robot bodies and everything else."""
        return self._margin

    @property
    def joint_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper joint position limits (rad)."""
        return self._lower.copy(), self._upper.copy()

    @property
    def velocity_limits(self) -> np.ndarray:
        """Joint velocity limits (rad/s) of the arm's model."""
        return np.array(arms.VELOCITY_LIMITS[self._config.model], dtype=float)

    @property
    def acceleration_limits(self) -> np.ndarray:
        """Default joint acceleration limits (rad/s^2), see :data:`ACCELERATION_LIMITS`."""
        return np.array(ACCELERATION_LIMITS[self._config.model], dtype=float)

    def _enable_self_collisions(self, plant: MultibodyPlant, pedestal: ModelInstanceIndex) -> None:
        inspector = self._checker.model().scene_graph().model_inspector()

        def has_geometry(body: RigidBody) -> bool:
            frame = plant.GetBodyFrameIdOrThrow(body.index())
            return len(inspector.GetGeometries(frame, Role.kProximity)) > 0

        # Joint distance between welded groups: anchored bodies form one group.
        group = {}
        for body in [plant.get_body(BodyIndex(i)) for i in range(plant.num_bodies())]:
            welded = plant.GetBodiesWeldedTo(body)
            group[body.index()] = min(b.index() for b in welded)
        neighbours: dict[BodyIndex, set] = {}
        for j in plant.GetJointIndices():
            joint = plant.get_joint(j)
            a, b = group[joint.parent_body().index()], group[joint.child_body().index()]
            if a != b:
                neighbours.setdefault(a, set()).add(b)
                neighbours.setdefault(b, set()).add(a)

        def hops(a: BodyIndex) -> dict:
            seen, frontier, k = {a: 0}, [a], 0
            while frontier:
                k += 1
                frontier = [n for f in frontier for n in neighbours.get(f, ()) if n not in seen]
                for n in frontier:
                    seen[n] = k
            return seen

        world = group[plant.world_body().index()]
        moving = [b for b in self._robot_bodies if has_geometry(b) and group[b.index()] != world]
        anchored = [b for b in self._robot_bodies if has_geometry(b) and group[b.index()] == world]
        anchored += [
            plant.get_body(b) for b in plant.GetBodyIndices(pedestal) if has_geometry(plant.get_body(b))
        ]
        for i, a in enumerate(moving):
            distance = hops(group[a.index()])
            for b in moving[i + 1 :]:
                if distance.get(group[b.index()], 99) >= 3:
                    self._checker.SetCollisionFilteredBetween(a, b, False)
            for b in anchored:
                # Forearm and beyond: the upper arm's convex hull grazes the pedestal
                # (within the margin) whenever the arm reaches down near its base.
                if distance.get(group[b.index()], 99) >= 3:
                    self._checker.SetCollisionFilteredBetween(a, b, False)

    def _full(self, q: np.ndarray, other_q: OtherPositions = None) -> np.ndarray:
        full = _to_full_q(self._q_default, self._q_index, q)
        if other_q is None:
            return full
        if isinstance(other_q, Mapping):
            for name, value in other_q.items():
                if name not in self._others:
                    raise UnknownNameError("other robot", name, self._others)
                full[self._others[name]] = self._check_shape(value, f"other_q[{name}]")
            return full
        if len(self._others) != 1:
            raise ConfigError(
                f"other_q must be a mapping robot -> joint positions when there are "
                f"{len(self._others)} other arms ({', '.join(self._others)})"
            )
        (index,) = self._others.values()
        full[index] = self._check_shape(other_q, "other_q")
        return full

    @staticmethod
    def _check_shape(q, what: str) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        if q.shape != (len(arms.JOINT_NAMES),) or not np.all(np.isfinite(q)):
            raise ConfigError(f"{what} must be {len(arms.JOINT_NAMES)} finite joint positions, got {q}")
        return q

    def _check_q(self, q, what: str) -> np.ndarray:
        q = self._check_shape(q, what)
        bad = np.flatnonzero((q < self._lower - 1e-9) | (q > self._upper + 1e-9))
        if bad.size:
            j = bad[0]
            raise PlanningError(
                f"{what} of {self._config.name}: {arms.JOINT_NAMES[j]} = {q[j]:.4f} rad is outside "
                f"the joint limits [{self._lower[j]:.4f}, {self._upper[j]:.4f}]"
            )
        return np.clip(q, self._lower, self._upper)

    # ------------------------------------------------------------ obstacles

    def set_obstacles(self, boxes: Sequence[Obstacle]) -> None:
        """Replaces the extra world obstacles by ``boxes``: each ``(X_WO, size)``, the
        box's centre pose in world and its edge (one number) or x, y, z edges (m).

        Collisions with them are reported as ``obstacle_<i>`` (i: index in ``boxes``).
        """
        self._checker.RemoveAllAddedCollisionShapes(_OBSTACLE_GROUP)
        self._obstacle_ids = []
        world = self._checker.plant().world_body()
        for i, (X_WO, size) in enumerate(boxes):
            box = _box(size, f"obstacle {i}")
            before = self._body_geometries(world)
            self._checker.AddCollisionShapeToBody(_OBSTACLE_GROUP, world, box, RigidTransform(X_WO))
            self._obstacle_ids += sorted(
                set(self._body_geometries(world)) - set(before), key=lambda g: g.get_value()
            )

    def set_held_part(self, X_CP: RigidTransform, size: float | Sequence[float]) -> None:
        """A box-shaped part held by the gripper: P's centre at ``X_CP`` in the cup
        body C (``<gripper>_cup``, origin on the cup face, +z out of the tool).

        For a cube of edge a hanging from the cup face: ``X_CP = RigidTransform([0, 0, a/2])``.
        Replaces any part held before. Collisions with it are reported as ``held_part``.
        The part itself may touch the cup face (same body); everything else is checked.
        """
        if self._cup is None:
            raise ConfigError(f"{self._config.name} has no gripper to hold a part")
        self.clear_held_part()
        box = _box(size, "held part")
        before = self._body_geometries(self._cup)
        self._checker.AddCollisionShapeToBody(_HELD_GROUP, self._cup, box, RigidTransform(X_CP))
        self._held_ids = sorted(
            set(self._body_geometries(self._cup)) - set(before), key=lambda g: g.get_value()
        )

    def clear_held_part(self) -> None:
        """The gripper holds nothing."""
        self._checker.RemoveAllAddedCollisionShapes(_HELD_GROUP)
        self._held_ids = []

    def _body_geometries(self, body: RigidBody) -> list[GeometryId]:
        inspector = self._checker.model_context().GetQueryObject().inspector()
        frame = self._checker.plant().GetBodyFrameIdOrThrow(body.index())
        return list(inspector.GetGeometries(frame, Role.kProximity))

    # ----------------------------------------------------------- collisions

    def collisions(self, q, other_q: OtherPositions = None) -> list[tuple[str, str]]:
        """The body pairs (robot body, other body) closer than ``margin`` at ``q``;
        empty when ``q`` is collision free. Added boxes are named ``obstacle_<i>``
        and ``held_part``."""
        full = self._full(self._check_shape(q, "q"), other_q)
        if self._checker.CheckConfigCollisionFree(full):
            return []
        return self._collision_pairs(full)

    def _collision_pairs(self, full: np.ndarray) -> list[tuple[str, str]]:
        plant = self._checker.plant()
        clearance = self._checker.CalcRobotClearance(full, influence_distance=self._margin)
        pairs: set[tuple[str, str]] = set()
        query = None
        cup = self._cup.index() if self._cup is not None else None
        world = plant.world_body().index()
        for r, o, distance in zip(
            clearance.robot_indices(), clearance.other_indices(), clearance.distances()
        ):
            if distance >= 0.0:
                continue
            robot_body, other_body = plant.get_body(r), plant.get_body(o)
            robot_name, other_name = robot_body.name(), other_body.name()
            # Added boxes hang on the world body (obstacles) and the cup (a held part).
            if (
                self._held_ids and cup in (robot_body.index(), other_body.index())
            ) or other_body.index() == world:
                query = query or self._checker.model_context().GetQueryObject()
                pairs |= self._geometry_pairs(query, robot_body, other_body)
            else:
                pairs.add((robot_name, other_name))
        return sorted(pairs)

    def _geometry_pairs(self, query, robot_body: RigidBody, other_body: RigidBody) -> set:
        """Names the geometries (added boxes included) of two bodies that touch."""
        pairs = set()
        geometry_a = self._body_geometries(robot_body)
        geometry_b = self._body_geometries(other_body)
        for a in geometry_a:
            for b in geometry_b:
                if a == b:
                    continue
                try:
                    distance = query.ComputeSignedDistancePairClosestPoints(a, b).distance
                except RuntimeError:  # a filtered pair or an unsupported shape pair
                    continue
                if distance < self._margin:
                    pairs.add((self._geometry_label(a, robot_body), self._geometry_label(b, other_body)))
        if not pairs:  # only the bodies are known
            pairs.add((robot_body.name(), other_body.name()))
        return pairs

    def _geometry_label(self, geometry: GeometryId, body: RigidBody) -> str:
        if geometry in self._obstacle_ids:
            return f"obstacle_{self._obstacle_ids.index(geometry)}"
        if geometry in self._held_ids:
            return "held_part"
        return body.name()

    def path_collisions(self, q_start, q_goal, other_q: OtherPositions = None) -> list[tuple[str, str]]:
        """The body pairs in collision anywhere on the straight joint segment
        ``q_start`` -> ``q_goal`` (checked every ``edge_step``); empty when it is free."""
        a = self._full(self._check_shape(q_start, "q_start"), other_q)
        b = self._full(self._check_shape(q_goal, "q_goal"), other_q)
        if self._checker.CheckEdgeCollisionFree(a, b):
            return []
        steps = max(1, math.ceil(np.linalg.norm(b - a) / self._checker.edge_step_size()))
        pairs: set[tuple[str, str]] = set()
        for s in np.linspace(0.0, 1.0, steps + 1):
            full = a + s * (b - a)
            if not self._checker.CheckConfigCollisionFree(full):
                pairs.update(self._collision_pairs(full))
        return sorted(pairs)

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

        Raises:
            PlanningError: start or goal outside the joint limits or in collision (the
                message names the bodies), or no path found within ``timeout`` s (the
                message names the bodies blocking the straight path).
        """
        if timeout <= 0:
            raise ConfigError(f"timeout must be > 0 s, got {timeout}")
        if int(seed) != seed or seed < 0:
            raise ConfigError(f"seed must be an integer >= 0, got {seed}")
        q_start = self._check_q(q_start, "start")
        q_goal = self._check_q(q_goal, "goal")
        base = self._full(q_start, other_q)
        goal_full = _to_full_q(base, self._q_index, q_goal)
        for what, q, full in (("start", q_start, base), ("goal", q_goal, goal_full)):
            if not self._checker.CheckConfigCollisionFree(full):
                raise PlanningError(
                    f"the {what} configuration {_fmt(q)} of {self._config.name} is in collision: "
                    f"{_fmt_pairs(self._collision_pairs(full))}"
                )
        if self._checker.CheckEdgeCollisionFree(base, goal_full):
            return [q_start, q_goal]
        path = self._rrt_connect(q_start, q_goal, base, timeout, int(seed), simplify)
        if path is None:
            raise PlanningError(
                f"no collision-free path for {self._config.name} from {_fmt(q_start)} to "
                f"{_fmt(q_goal)} found within {timeout:g} s; the straight path is blocked by "
                f"{_fmt_pairs(self.path_collisions(q_start, q_goal, other_q))}"
            )
        return path

    def _rrt_connect(
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
        finds a collision the coarse search missed, searched again at ``edge_step``."""
        fine = self._checker.edge_step_size()
        steps = [self._search_step, fine] if self._search_step > fine else [fine]
        for step in steps:
            path = self._ompl_path(q_start, q_goal, base, timeout, seed, simplify, step)
            if path is None:
                return None
            edges = [
                (_to_full_q(base, self._q_index, a), _to_full_q(base, self._q_index, b))
                for a, b in itertools.pairwise(path)
            ]
            if all(self._checker.CheckEdgesCollisionFree(edges, Parallelism(1))):
                _log.debug("RRTConnect: %d waypoints (edges checked every %g rad)", len(path), step)
                return path
            _log.debug("RRTConnect path at %g rad collides at %g rad: searching again", step, fine)
        raise PlanningError(
            f"OMPL returned a path from {_fmt(q_start)} to {_fmt(q_goal)} with a "
            f"segment in collision (a bug: please report it)"
        )

    def _ompl_path(
        self,
        q_start: np.ndarray,
        q_goal: np.ndarray,
        base: np.ndarray,
        timeout: float,
        seed: int,
        simplify: bool,
        step: float,
    ) -> list[np.ndarray] | None:
        n = len(q_start)
        index = self._q_index
        checker = self._checker
        fine = checker.edge_step_size()

        def to_full(state) -> np.ndarray:
            return _to_full_q(base, index, [state[i] for i in range(n)])

        checker.set_edge_step_size(step)
        try:
            with _ompl_quiet():
                # OMPL ignores seed 0; every RNG created after this call is seeded from it.
                ou.RNG.setSeed(seed + 1)
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
                start, goal = space.allocState(), space.allocState()
                for i in range(n):
                    start[i], goal[i] = float(q_start[i]), float(q_goal[i])
                setup.setStartAndGoalStates(start, goal)
                setup.solve(float(timeout))
                if not setup.haveExactSolutionPath():
                    return None
                solution = setup.getSolutionPath()
                if simplify:
                    # Not time-limited (so deterministic): shortcut, drop vertices.
                    simplifier = setup.getPathSimplifier()
                    simplifier.ropeShortcutPath(solution)
                    simplifier.reduceVertices(solution)
                path = [np.array([s[i] for i in range(n)]) for s in solution.getStates()]
        finally:
            checker.set_edge_step_size(fine)
        path[0], path[-1] = q_start.copy(), q_goal.copy()
        return path

    # ------------------------------------------------------------ kinematics

    def _frame(self, frame: str):
        if frame not in self._frame_names:
            raise UnknownNameError("tool frame", frame, self._frame_names)
        return self._ik_plant.GetFrameByName(self._frame_names[frame])

    def forward_kinematics(self, q, frame: str = "tip") -> RigidTransform:
        """``X_WE``: the world pose of tool frame E (``tip``, ``suction_cup``, ``tool0``) at ``q``."""
        tool = self._frame(frame)
        q_ik = np.zeros(self._ik_plant.num_positions())
        q_ik[self._ik_index] = self._check_shape(q, "q")
        self._ik_plant.SetPositions(self._ik_context, q_ik)
        return self._X_WB @ tool.CalcPoseInWorld(self._ik_context)

    def ik(
        self,
        X_WE: RigidTransform,
        *,
        frame: str = "tip",
        q_seed=None,
        other_q: OtherPositions = None,
        check_collisions: bool = True,
        position_tolerance: float = 1e-4,
        orientation_tolerance: float = 1e-3,
        num_seeds: int = 8,
    ) -> np.ndarray:
        """Joint positions putting tool frame E at the world pose ``X_WE``, within the
        joint limits, collision free (unless ``check_collisions`` is False), nearest
        ``q_seed`` (default: the arm's initial pose).

        Frames: ``tip`` (``<gripper>_tip``, the physical cup face), ``suction_cup``
        (``<gripper>_suction_cup``, the course's frame, 1 cm off the flange), ``tool0``.
        Solves Drake's InverseKinematics (SNOPT) from ``q_seed``; when that solution is
        not usable, from the arm's named poses and a few fixed random seeds, and keeps
        the usable solution nearest ``q_seed``.

        Raises:
            PlanningError: ``unreachable`` (with the distance and angle by which the
                closest solution misses the pose), reachable only ``outside the joint
                limits``, or every solution found is in collision (naming the bodies).
        """
        tool = self._frame(frame)
        q_seed = self._check_shape(self._q_default[self._q_index] if q_seed is None else q_seed, "q_seed")
        if num_seeds < 1:
            raise ConfigError(f"num_seeds must be >= 1, got {num_seeds}")
        X_BE = self._X_WB.inverse() @ RigidTransform(X_WE)
        base = self._full(q_seed, other_q)

        def usable(q: np.ndarray) -> bool:
            if not check_collisions:
                return True
            return self._checker.CheckConfigCollisionFree(_to_full_q(base, self._q_index, q))

        seeds = self._ik_seeds(q_seed, num_seeds)
        solutions: list[np.ndarray] = []
        for k, seed in enumerate(seeds):
            q = self._solve_ik(tool, X_BE, seed, q_seed, position_tolerance, orientation_tolerance)
            if q is None:
                continue
            if k == 0 and usable(q):
                return q
            solutions.append(q)
        free = [q for q in solutions if usable(q)]
        if free:
            return min(free, key=lambda q: float(np.linalg.norm(q - q_seed)))
        where = f"{frame} pose {_fmt_pose(RigidTransform(X_WE))} for {self._config.name}"
        if solutions:
            raise self._ik_collision_error(where, solutions, q_seed, base)
        # Without joint limits: a solution may only need whole turns to fit in them.
        for seed in seeds[:3]:
            q = self._solve_ik(
                tool, X_BE, seed, q_seed, position_tolerance, orientation_tolerance, joint_limits=False
            )
            if q is None:
                continue
            wrapped, outside = self._wrap_into_limits(q, q_seed)
            if np.all(outside <= 0) and usable(wrapped):
                return wrapped
            if np.any(outside > 0):
                raise self._joint_limit_error(where, q, outside)
        position_error, angle_error = self._closest_miss(tool, X_BE, seeds[:3])
        raise PlanningError(
            f"unreachable: the {where}: the closest solution misses it by "
            f"{position_error * 1000:.0f} mm and {math.degrees(angle_error):.1f} deg"
        )

    def _ik_collision_error(
        self, where: str, solutions: list[np.ndarray], q_seed: np.ndarray, base: np.ndarray
    ) -> PlanningError:
        """The error for IK whose every solution is in collision: the bodies touching
        at the solution nearest ``q_seed`` (``base``: the full configuration)."""
        nearest = min(solutions, key=lambda q: float(np.linalg.norm(q - q_seed)))
        full = _to_full_q(base, self._q_index, nearest)
        return PlanningError(
            f"every IK solution of the {where} is in collision; the nearest "
            f"{_fmt(nearest)}: {_fmt_pairs(self._collision_pairs(full))}"
        )

    def _wrap_into_limits(self, q: np.ndarray, q_seed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``q`` shifted by whole turns nearest ``q_seed``, then by a turn into the joint
        limits where that helps; and how far (rad) each joint is still outside them
        (<= 0: inside)."""
        wrapped = q + 2 * np.pi * np.round((q_seed - q) / (2 * np.pi))
        wrapped = np.where(wrapped > self._upper, wrapped - 2 * np.pi, wrapped)
        wrapped = np.where(wrapped < self._lower, wrapped + 2 * np.pi, wrapped)
        outside = np.maximum(wrapped - self._upper, self._lower - wrapped)
        return wrapped, outside

    def _joint_limit_error(self, where: str, q: np.ndarray, outside: np.ndarray) -> PlanningError:
        """The error for a pose reachable only outside the joint limits: the joint
        furthest ``outside`` them and its value in the solution ``q``."""
        j = int(np.argmax(outside))
        return PlanningError(
            f"the {where} is reachable only outside the joint limits: "
            f"{arms.JOINT_NAMES[j]} would be {q[j]:.3f} rad, limits "
            f"[{self._lower[j]:.3f}, {self._upper[j]:.3f}]"
        )

    def _ik_seeds(self, q_seed: np.ndarray, count: int) -> list[np.ndarray]:
        """``q_seed``, then the arm's named poses (nearest first), then fixed random ones."""
        named = []
        for name in _SEED_POSES:
            try:
                named.append(arms.named_pose(name, self._config))
            except UnknownNameError:  # a robot without that course pose
                continue
        named.sort(key=lambda q: float(np.linalg.norm(q - q_seed)))
        rng = np.random.default_rng(0)
        seeds = [q_seed] + named
        while len(seeds) < count:
            seeds.append(rng.uniform(self._lower, self._upper))
        return seeds[: max(count, 1)]

    def _new_ik(self, joint_limits: bool) -> InverseKinematics:
        return InverseKinematics(self._ik_plant, with_joint_limits=joint_limits)

    def _solve_ik(
        self,
        tool,
        X_BE: RigidTransform,
        seed: np.ndarray,
        q_nominal: np.ndarray,
        position_tolerance: float,
        orientation_tolerance: float,
        joint_limits: bool = True,
    ) -> np.ndarray | None:
        ik = self._new_ik(joint_limits)
        base = self._ik_plant.world_frame()
        p = X_BE.translation()
        ik.AddPositionConstraint(tool, np.zeros(3), base, p - position_tolerance, p + position_tolerance)
        ik.AddOrientationConstraint(base, X_BE.rotation(), tool, RotationMatrix(), orientation_tolerance)
        prog = ik.get_mutable_prog()
        q = ik.q()
        nominal = np.zeros(len(q))
        nominal[self._ik_index] = q_nominal
        prog.AddQuadraticErrorCost(np.eye(len(q)), nominal, q)
        guess = np.zeros(len(q))
        guess[self._ik_index] = seed
        prog.SetInitialGuess(q, guess)
        result = Solve(prog)
        if not result.is_success():
            return None
        solution = result.GetSolution(q)[self._ik_index]
        if joint_limits:
            solution = np.clip(solution, self._lower, self._upper)
        return solution

    def _closest_miss(self, tool, X_BE: RigidTransform, seeds: list[np.ndarray]) -> tuple[float, float]:
        """(position error m, angle error rad) of the best least-squares IK solution."""
        best = (math.inf, math.inf)
        for seed in seeds:
            ik = self._new_ik(True)
            base = self._ik_plant.world_frame()
            ik.AddPositionCost(base, X_BE.translation(), tool, np.zeros(3), np.eye(3))
            ik.AddOrientationCost(base, X_BE.rotation(), tool, RotationMatrix(), 0.1)
            prog = ik.get_mutable_prog()
            guess = np.zeros(self._ik_plant.num_positions())
            guess[self._ik_index] = seed
            prog.SetInitialGuess(ik.q(), guess)
            result = Solve(prog)
            self._ik_plant.SetPositions(self._ik_context, result.GetSolution(ik.q()))
            X_BT = tool.CalcPoseInWorld(self._ik_context)
            error = (
                float(np.linalg.norm(X_BT.translation() - X_BE.translation())),
                float(X_BT.rotation().InvertAndCompose(X_BE.rotation()).ToAngleAxis().angle()),
            )
            best = min(best, error)
        return best

    def cartesian_path(
        self,
        q_start,
        waypoints: Sequence[RigidTransform],
        *,
        frame: str = "tip",
        max_step: float = 0.005,
        max_rotation_step: float = 0.05,
        jump_threshold: float | None = 0.5,
        avoid_collisions: bool = True,
        other_q: OtherPositions = None,
    ) -> tuple[list[np.ndarray], float]:
        """A straight-line tool motion through world poses, like MoveIt's
        ``compute_cartesian_path``.

        From the tool pose at ``q_start`` the pose of frame E moves in straight lines
        (rotation by slerp) through ``waypoints`` (each an ``X_WE``), in steps of at most
        ``max_step`` m and ``max_rotation_step`` rad. Each step's IK is seeded by the
        previous step's solution and kept nearest it. The path stops at the first step
        that is unreachable, moves some joint by more than ``jump_threshold`` rad (a
        jump to another IK branch; None: no check) or, with ``avoid_collisions``,
        collides (on the joint segment from the previous step).

        Returns:
            The joint path (starting with ``q_start``) and the fraction of the steps
            achieved, 0...1 (1.0: the whole motion).
        """
        if max_step <= 0 or max_rotation_step <= 0:
            raise ConfigError(
                f"max_step and max_rotation_step must be > 0, got {max_step}, {max_rotation_step}"
            )
        if jump_threshold is not None and jump_threshold <= 0:
            raise ConfigError(f"jump_threshold must be > 0 rad or None, got {jump_threshold}")
        tool = self._frame(frame)
        q_start = self._check_q(q_start, "q_start")
        base = self._full(q_start, other_q)
        targets = _interpolate_poses(
            self.forward_kinematics(q_start, frame),
            [RigidTransform(X) for X in waypoints],
            max_step,
            max_rotation_step,
        )
        path = [q_start]
        if not targets:
            return path, 1.0
        X_BW = self._X_WB.inverse()
        for X_WE in targets:
            previous = path[-1]
            q = self._solve_ik(tool, X_BW @ X_WE, previous, previous, 1e-4, 1e-3)
            reason = None
            if q is None:
                reason = f"unreachable at {_fmt_pose(X_WE)}"
            elif jump_threshold is not None and np.max(np.abs(q - previous)) > jump_threshold:
                reason = f"joint jump of {np.max(np.abs(q - previous)):.3f} rad at {_fmt_pose(X_WE)}"
            elif avoid_collisions and not self._checker.CheckEdgeCollisionFree(
                _to_full_q(base, self._q_index, previous), _to_full_q(base, self._q_index, q)
            ):
                full = _to_full_q(base, self._q_index, q)
                reason = (
                    f"collision at {_fmt_pose(X_WE)}: "
                    f"{_fmt_pairs(self._collision_pairs(full)) or 'on the way'}"
                )
            if reason is not None:
                _log.info(
                    "cartesian path of %s stops after %d of %d steps: %s",
                    self._config.name,
                    len(path) - 1,
                    len(targets),
                    reason,
                )
                break
            path.append(q)
        return path, (len(path) - 1) / len(targets)

    # ---------------------------------------------------------------- timing

    def time_parameterize(
        self,
        path: Sequence[np.ndarray],
        *,
        velocity_scale: float = 1.0,
        acceleration_scale: float = 1.0,
        acceleration_limits: Sequence[float] | None = None,
        start_time: float = 0.0,
        turn_tolerance: float = 0.002,
    ) -> PiecewisePolynomial:
        """A rest-to-rest joint trajectory along ``path`` (joint waypoints) with TOPP-RA.

        Joint velocities stay within ``velocity_scale`` times the arm's velocity limits
        and accelerations within ``acceleration_scale`` times ``acceleration_limits``
        (default :data:`ACCELERATION_LIMITS`), exactly (the returned cubic pieces are
        checked and, if needed, slowed). The arm stops at every waypoint where its path
        turns so that a smooth curve through it would leave the straight segments by
        more than ``turn_tolerance`` (rad, about the shorter segment times the turn
        angle): so a planned path's collision-checked segments are followed exactly.
        Elsewhere (a Cartesian path's dense waypoints) it follows a cubic spline
        through the waypoints without stopping.

        Returns:
            A ``PiecewisePolynomial`` of the six joint positions, from ``start_time``, at
            rest at both ends; ``value(end_time())`` is the last waypoint.
        """
        if not 0 < velocity_scale <= 1 or not 0 < acceleration_scale <= 1:
            raise ConfigError(
                f"velocity_scale and acceleration_scale must be in (0, 1], got "
                f"{velocity_scale}, {acceleration_scale}"
            )
        vlim = self.velocity_limits * velocity_scale
        alim = (
            self.acceleration_limits
            if acceleration_limits is None
            else self._check_shape(acceleration_limits, "acceleration_limits")
        )
        if np.any(alim <= 0):
            raise ConfigError(f"acceleration_limits must be > 0, got {alim}")
        points = [self._check_shape(q, f"path[{i}]") for i, q in enumerate(path)]
        if not points:
            raise ConfigError("path needs at least one waypoint")
        return time_parameterize(
            points, vlim, alim * acceleration_scale, start_time=start_time, turn_tolerance=turn_tolerance
        )


def _to_full_q(base: np.ndarray, index: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``base`` (a full plant configuration) with the entries ``index`` set to ``q``."""
    full = base.copy()
    full[index] = q
    return full


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

    See :meth:`ArmPlanner.time_parameterize`. ``grid_step`` (rad of path length) is
    the largest spacing of TOPP-RA's grid.
    """
    # toppra imports scipy and matplotlib (about 1 s): only when needed.
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


def _distinct_waypoints(path: Sequence[np.ndarray]) -> list[np.ndarray]:
    """``path``'s waypoints as float arrays, without repeats (within 1e-9 rad)."""
    points = [np.asarray(path[0], dtype=float)]
    for q in path[1:]:
        q = np.asarray(q, dtype=float)
        if np.linalg.norm(q - points[-1]) > 1e-9:
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
            f"{_fmt(waypoints[0])} to {_fmt(waypoints[-1])}"
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


def _interpolate_poses(
    X_start: RigidTransform, waypoints: list[RigidTransform], max_step: float, max_rotation_step: float
) -> list[RigidTransform]:
    """Poses along straight lines (slerped rotations) through ``waypoints``, at most
    ``max_step`` m and ``max_rotation_step`` rad apart, ``X_start`` excluded."""
    poses, previous = [], X_start
    for X in waypoints:
        p0, p1 = previous.translation(), X.translation()
        angle = previous.rotation().InvertAndCompose(X.rotation()).ToAngleAxis().angle()
        # (1e-9: 0.1 m in 5 mm steps is 20 steps despite rounding)
        steps = max(
            1,
            math.ceil(np.linalg.norm(p1 - p0) / max_step - 1e-9),
            math.ceil(angle / max_rotation_step - 1e-9),
        )
        poses += [interpolate_pose(previous, X, k / steps) for k in range(1, steps + 1)]
        previous = X
    return poses


def _box(size: float | Sequence[float], what: str) -> Box:
    edges = np.broadcast_to(np.asarray(size, dtype=float), (3,))
    if not np.all(edges > 0):
        raise ConfigError(f"{what}: box size must be one edge or x, y, z edges > 0 m, got {size}")
    return Box(*edges)


def _fmt(q: np.ndarray) -> str:
    return "[" + ", ".join(f"{v:.3f}" for v in q) + "]"


def _fmt_pose(X: RigidTransform) -> str:
    p = X.translation()
    return f"p=({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f})"


def _fmt_pairs(pairs: list[tuple[str, str]]) -> str:
    return ", ".join(f"{a} / {b}" for a, b in pairs)
