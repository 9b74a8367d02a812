"""The collision model of one arm in the cell: Drake's ``SceneGraphCollisionChecker``.

The checker works on a ``RobotDiagram`` of the whole static cell (every model
:func:`~omtp_drake.cell.station.add_cell_models` adds, without parts). The robot is
the arm and its gripper; everything else (the other arms at given joint positions,
pedestals, bins, conveyor, floor) is environment. What is added to it (obstacle
boxes, a held part) is the planning scene's business
(:class:`~omtp_drake.control.motion.scene.PlanningScene`). A pair is in collision
when its signed distance is below ``margin``.

Self collisions. The station filters every pair within one arm (the simulation
needs no self contact). :func:`enable_self_collisions` re-enables, for planning, the
pairs at least three joints apart (e.g. upper arm / wrist 2, forearm / gripper) and
the arm's links three or more joints away from its pedestal and base (forearm,
wrists, gripper). Pairs two joints apart stay filtered: their convex-hull collision
shapes overlap at ordinary poses (the forearm and wrist 2 hulls touch in 40 % of
random configurations).

Configurations: ``q`` are the planned arm's six joint positions; a *full*
configuration is the checker plant's (every arm's joints).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import TypeAlias

import numpy as np
from pydrake.common import Parallelism
from pydrake.geometry import GeometryId, Role
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, ModelInstanceIndex, RigidBody
from pydrake.planning import RobotDiagramBuilder, SceneGraphCollisionChecker

from omtp_drake.cell import arms
from omtp_drake.cell.station import ArmHandles, add_cell_models
from omtp_drake.control.motion.formatting import fmt_pairs, fmt_q
from omtp_drake.control.motion.scene import PlanningScene
from omtp_drake.errors import ConfigError, GoalInCollisionError, UnknownNameError
from omtp_drake.scenario import RobotConfig, Scenario

#: Other arms' joint positions: one array (when there is one other arm) or by robot name.
OtherPositions: TypeAlias = np.ndarray | Sequence[float] | Mapping[str, Sequence[float]] | None


class CollisionModel:
    """Collision queries for ``robot`` (an arm of ``scenario``) against the cell.

    Args:
        scenario: the cell.
        robot: the planned arm's name.
        margin: clearance (m) every robot body keeps to everything else.
        edge_step: joint-space distance (rad) between two checked configurations of
            a straight joint segment.
        self_collisions: also check the arm against itself (see module doc).
    """

    def __init__(
        self, scenario: Scenario, robot: str, *, margin: float, edge_step: float, self_collisions: bool
    ) -> None:
        builder = RobotDiagramBuilder(time_step=0.0)
        models = add_cell_models(builder.plant(), builder.scene_graph(), scenario, parts=False)
        builder.plant().Finalize()
        handles = models.arms[robot]
        robot_instances = _robot_instances(builder.plant(), handles, scenario)
        self.checker = SceneGraphCollisionChecker(
            model=builder.Build(),
            robot_model_instances=robot_instances,
            edge_step_size=edge_step,
            env_collision_padding=margin,
            self_collision_padding=margin,
            implicit_context_parallelism=Parallelism(1),
        )
        self.margin = float(margin)
        self.config: RobotConfig = handles.config
        plant = self.checker.plant()
        self._index_joints(plant, models.arms)
        gripper = self.config.gripper
        self.cup: RigidBody | None = (
            plant.GetBodyByName(f"{gripper}_cup", handles.gripper) if gripper else None
        )
        robot_bodies = [plant.get_body(b) for inst in robot_instances for b in plant.GetBodyIndices(inst)]
        if self_collisions:
            enable_self_collisions(self.checker, robot_bodies, handles.pedestal)
        #: What is added to the cell: obstacles and a held part.
        self.scene = PlanningScene(self.checker, self.cup, robot)

    def _index_joints(self, plant: MultibodyPlant, handles: Mapping[str, ArmHandles]) -> None:
        """Where each arm's joints sit in the full configurations, and the default full
        configuration (every arm at its initial pose)."""

        def joint_indices(instance: ModelInstanceIndex, name: str) -> np.ndarray:
            return np.array(
                [plant.GetJointByName(f"{name}_{j}", instance).position_start() for j in arms.JOINT_NAMES]
            )

        robot = self.config.name
        self.q_index = joint_indices(handles[robot].arm, robot)
        self._others: dict[str, tuple[np.ndarray, RobotConfig]] = {}
        self._q_default = plant.GetPositions(plant.CreateDefaultContext())
        for name, other in handles.items():
            if name != robot:
                self._others[name] = (joint_indices(other.arm, name), other.config)
                self._q_default[self._others[name][0]] = arms.named_pose(
                    other.config.initial_pose, other.config
                )
        self._q_default[self.q_index] = arms.named_pose(self.config.initial_pose, self.config)

    @property
    def q_initial(self) -> np.ndarray:
        """The planned arm's initial joint positions."""
        return self._q_default[self.q_index].copy()

    # -------------------------------------------------------- configurations

    def full(self, q: np.ndarray, other_q: OtherPositions = None) -> np.ndarray:
        """The full configuration with the planned arm at ``q`` and the other arms at
        ``other_q`` (default: their initial poses)."""
        full = self.with_arm(self._q_default, q)
        if other_q is None:
            return full
        if isinstance(other_q, Mapping):
            for name, value in other_q.items():
                if name not in self._others:
                    raise UnknownNameError("other robot", name, self._others)
                index, config = self._others[name]
                full[index] = arms.check_joint_positions(value, config)
            return full
        if len(self._others) != 1:
            raise ConfigError(
                f"other_q must be a mapping robot -> joint positions when there are "
                f"{len(self._others)} other arms ({', '.join(self._others)})"
            )
        ((index, config),) = self._others.values()
        full[index] = arms.check_joint_positions(other_q, config)
        return full

    def with_arm(self, full: np.ndarray, q: np.ndarray | Sequence[float]) -> np.ndarray:
        """``full`` (a full configuration) with the planned arm at ``q``."""
        out = full.copy()
        out[self.q_index] = q
        return out

    def filter_pairs(self, pairs: Iterable[tuple[str, str]]) -> list[tuple[str, str]]:
        """Stops checking the named body pairs (MoveIt's disabled collisions); returns
        the pairs it filtered. Pairs with a body the checker lacks, of a body with
        itself, or of two environment bodies (never checked) are skipped."""
        plant = self.checker.plant()
        filtered = []
        matrix = self.checker.GetFilteredCollisionMatrix().copy()  # set once (see enable_self_collisions)
        for a, b in pairs:
            if a == b or not (plant.HasBodyNamed(a) and plant.HasBodyNamed(b)):
                continue
            body_a, body_b = plant.GetBodyByName(a), plant.GetBodyByName(b)
            if self.checker.IsPartOfRobot(body_a) or self.checker.IsPartOfRobot(body_b):
                i, j = int(body_a.index()), int(body_b.index())
                if matrix[i, j] != -1:  # -1: two anchored bodies, never checked
                    matrix[i, j] = matrix[j, i] = 1
                filtered.append((a, b))
        if filtered:
            self.checker.SetCollisionFilterMatrix(matrix)
        return filtered

    # -------------------------------------------------------------- queries

    def config_free(self, full: np.ndarray) -> bool:
        """Is the full configuration collision free?"""
        return self.checker.CheckConfigCollisionFree(full)

    def edge_free(self, a: np.ndarray, b: np.ndarray) -> bool:
        """Is the straight segment between two full configurations free (checked every ``edge_step``)?"""
        return self.checker.CheckEdgeCollisionFree(a, b)

    def pairs(self, full: np.ndarray) -> list[tuple[str, str]]:
        """The (robot body, other body) pairs closer than ``margin`` at a full
        configuration; added boxes are named by the planning scene's labels."""
        plant = self.checker.plant()
        clearance = self.checker.CalcRobotClearance(full, influence_distance=self.margin)
        pairs: set[tuple[str, str]] = set()
        cup = self.cup.index() if self.cup is not None else None
        world = plant.world_body().index()
        for r, o, distance in zip(
            clearance.robot_indices(), clearance.other_indices(), clearance.distances()
        ):
            if distance >= 0.0:
                continue
            robot_body, other_body = plant.get_body(r), plant.get_body(o)
            # Added boxes hang on the world body (obstacles) and the cup (a held part).
            if (
                self.scene.holds_part and cup in (robot_body.index(), other_body.index())
            ) or other_body.index() == world:
                pairs |= self._geometry_pairs(robot_body, other_body)
            else:
                pairs.add((robot_body.name(), other_body.name()))
        return sorted(pairs)

    def _geometry_pairs(self, robot_body: RigidBody, other_body: RigidBody) -> set[tuple[str, str]]:
        """Names the geometries (added boxes included) of two bodies that touch."""
        query = self.checker.model_context().GetQueryObject()
        pairs = set()
        geometry_b: list[GeometryId] = self.scene.body_geometries(other_body)
        for a in self.scene.body_geometries(robot_body):
            for b in geometry_b:
                if a == b:
                    continue
                try:
                    distance = query.ComputeSignedDistancePairClosestPoints(a, b).distance
                except RuntimeError:  # a filtered pair or an unsupported shape pair
                    continue
                if distance < self.margin:
                    pairs.add((self.scene.label(a, robot_body), self.scene.label(b, other_body)))
        if not pairs:  # only the bodies are known
            pairs.add((robot_body.name(), other_body.name()))
        return pairs

    def require_free(self, what: str, q: np.ndarray, full: np.ndarray) -> None:
        """GoalInCollisionError naming the touching pairs unless the full configuration
        ``full`` (the arm at ``q``, the ``what`` configuration: a goal) is collision free."""
        if not self.config_free(full):
            raise GoalInCollisionError(
                f"the {what} configuration {fmt_q(q)} of {self.config.name} is in collision: "
                f"{fmt_pairs(self.pairs(full))}"
            )

    def ik_error(
        self, where: str, solutions: list[np.ndarray], q_seed: np.ndarray, base: np.ndarray
    ) -> GoalInCollisionError:
        """The error for IK whose every solution is in collision: the pairs touching at
        the solution nearest ``q_seed`` (``base``: the full configuration)."""
        nearest = min(solutions, key=lambda q: float(np.linalg.norm(q - q_seed)))
        return GoalInCollisionError(
            f"every IK solution of the {where} is in collision; the nearest "
            f"{fmt_q(nearest)}: {fmt_pairs(self.pairs(self.with_arm(base, nearest)))}"
        )

    def path_pairs(self, a: np.ndarray, b: np.ndarray) -> list[tuple[str, str]]:
        """The pairs in collision anywhere on the straight segment between two full
        configurations (checked every ``edge_step``); empty when it is free."""
        if self.checker.CheckEdgeCollisionFree(a, b):
            return []
        steps = max(1, math.ceil(np.linalg.norm(b - a) / self.checker.edge_step_size()))
        pairs: set[tuple[str, str]] = set()
        for s in np.linspace(0.0, 1.0, steps + 1):
            full = a + s * (b - a)
            if not self.checker.CheckConfigCollisionFree(full):
                pairs.update(self.pairs(full))
        return sorted(pairs)


def _robot_instances(
    plant: MultibodyPlant, handles: ArmHandles, scenario: Scenario
) -> list[ModelInstanceIndex]:
    """The model instances the planner moves: the arm, its gripper if it has one, and what
    the student's files hang on them (a bumper written into the gripper's link is the
    gripper's geometry, as MoveIt takes a link's collisions; as environment the checker
    would never test it against the cell)."""
    robot = [handles.arm] + ([handles.gripper] if handles.gripper is not None else [])
    for model in scenario.models:
        if model.parent and plant.HasFrameNamed(model.parent) and plant.HasModelInstanceNamed(model.name):
            if plant.GetFrameByName(model.parent).body().model_instance() in robot:
                robot.append(plant.GetModelInstanceByName(model.name))
    return robot


def _joint_hops(plant: MultibodyPlant) -> tuple[dict[BodyIndex, BodyIndex], dict[BodyIndex, set]]:
    """Each body's welded group (named by its lowest body index; anchored bodies
    share the world's) and each group's neighbours across one joint."""
    group = {}
    for body in [plant.get_body(BodyIndex(i)) for i in range(plant.num_bodies())]:
        group[body.index()] = min(b.index() for b in plant.GetBodiesWeldedTo(body))
    neighbours: dict[BodyIndex, set] = {}
    for j in plant.GetJointIndices():
        joint = plant.get_joint(j)
        a, b = group[joint.parent_body().index()], group[joint.child_body().index()]
        if a != b:
            neighbours.setdefault(a, set()).add(b)
            neighbours.setdefault(b, set()).add(a)
    return group, neighbours


def enable_self_collisions(
    checker: SceneGraphCollisionChecker, robot_bodies: list[RigidBody], pedestal: ModelInstanceIndex
) -> None:
    """Re-enables the robot's pairs at least three joints apart, and those of its
    moving bodies with its anchored ones and its pedestal (see module doc)."""
    plant = checker.plant()
    inspector = checker.model().scene_graph().model_inspector()

    def has_geometry(body: RigidBody) -> bool:
        frame = plant.GetBodyFrameIdOrThrow(body.index())
        return len(inspector.GetGeometries(frame, Role.kProximity)) > 0

    group, neighbours = _joint_hops(plant)

    def hops(a: BodyIndex) -> dict:
        seen, frontier, k = {a: 0}, [a], 0
        while frontier:
            k += 1
            frontier = [n for f in frontier for n in neighbours.get(f, ()) if n not in seen]
            for n in frontier:
                seen[n] = k
        return seen

    world = group[plant.world_body().index()]
    moving = [b for b in robot_bodies if has_geometry(b) and group[b.index()] != world]
    anchored = [b for b in robot_bodies if has_geometry(b) and group[b.index()] == world]
    anchored += [plant.get_body(b) for b in plant.GetBodyIndices(pedestal) if has_geometry(plant.get_body(b))]
    # The pairs are un-filtered in a copy of the checker's filter matrix, set once: each
    # SetCollisionFilteredBetween call applied the whole matrix again (~24 pairs an arm: a
    # quarter of a planner's build, 0.22 -> 0.17 CPU s, in every run that plans).
    matrix = checker.GetFilteredCollisionMatrix().copy()
    for i, a in enumerate(moving):
        distance = hops(group[a.index()])
        for b in moving[i + 1 :]:
            if distance.get(group[b.index()], 99) >= 3:
                _unfilter(matrix, a, b)
        for b in anchored:
            # Forearm and beyond: the upper arm's convex hull grazes the pedestal
            # (within the margin) whenever the arm reaches down near its base.
            if distance.get(group[b.index()], 99) >= 3:
                _unfilter(matrix, a, b)
    checker.SetCollisionFilterMatrix(matrix)


def _unfilter(matrix: np.ndarray, a: RigidBody, b: RigidBody) -> None:
    """Marks the pair (a, b) checked in a collision filter matrix (0: not filtered)."""
    matrix[int(a.index()), int(b.index())] = matrix[int(b.index()), int(a.index())] = 0
