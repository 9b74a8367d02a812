"""Kinematics of one arm for planning: forward kinematics and inverse kinematics
with seeds (Drake's ``InverseKinematics``, SNOPT).

The model is the arm and its gripper alone, base B at the origin; world poses are
``X_WB`` times base poses. Notation: ``X_WE`` is the world pose of a tool frame E
(``tip``, ``suction_cup``, ``tool0``), ``X_BE`` its pose in the arm's base.
"""

from __future__ import annotations

import math

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import InverseKinematics
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame
from pydrake.solvers import Solve

from omtp_drake.cell import arms
from omtp_drake.control.motion.collision import CollisionModel
from omtp_drake.control.motion.formatting import fmt_pose
from omtp_drake.errors import ConfigError, UnknownNameError, UnreachableError
from omtp_drake.scenario import RobotConfig, Scenario

#: The course's named poses (short names) that seed IK after the caller's seed.
_SEED_POSES = ("Home", "PreGrasp", "Place", "Up")


class ArmKinematics:
    """Forward and inverse kinematics of ``robot`` (an arm of ``scenario``)."""

    def __init__(self, scenario: Scenario, robot: RobotConfig) -> None:
        self.config = robot
        self.X_WB = arms.base_pose(robot)
        self._plant: MultibodyPlant = arms.make_control_plant(robot, scenario.gravity)
        self._context = self._plant.CreateDefaultContext()
        self._index = np.array(
            [self._plant.GetJointByName(f"{robot.name}_{j}").position_start() for j in arms.JOINT_NAMES]
        )
        self._frame_names = arms.tool_frame_names(robot)
        limit = robot.joint_limit
        self.lower = np.full(len(arms.JOINT_NAMES), -limit)
        self.upper = np.full(len(arms.JOINT_NAMES), limit)

    def frame(self, frame: str) -> Frame:
        """The tool frame named ``frame`` (``tip``, ``suction_cup``, ``tool0``)."""
        if frame not in self._frame_names:
            raise UnknownNameError("tool frame", frame, self._frame_names)
        return self._plant.GetFrameByName(self._frame_names[frame])

    def forward_kinematics(self, q: np.ndarray, frame: str = "tip") -> RigidTransform:
        """``X_WE`` at joint positions ``q`` (already checked)."""
        tool = self.frame(frame)
        self._set(q)
        return self.X_WB @ tool.CalcPoseInWorld(self._context)

    def _set(self, q: np.ndarray) -> None:
        q_full = np.zeros(self._plant.num_positions())
        q_full[self._index] = q
        self._plant.SetPositions(self._context, q_full)

    def solve(
        self,
        tool: Frame,
        X_BE: RigidTransform,
        seed: np.ndarray,
        q_nominal: np.ndarray,
        position_tolerance: float,
        orientation_tolerance: float,
        joint_limits: bool = True,
    ) -> np.ndarray | None:
        """One IK solve from ``seed``, nearest ``q_nominal``; None if SNOPT fails."""
        ik = InverseKinematics(self._plant, with_joint_limits=joint_limits)
        base = self._plant.world_frame()
        p = X_BE.translation()
        ik.AddPositionConstraint(tool, np.zeros(3), base, p - position_tolerance, p + position_tolerance)
        ik.AddOrientationConstraint(base, X_BE.rotation(), tool, RotationMatrix(), orientation_tolerance)
        prog = ik.get_mutable_prog()
        q = ik.q()
        nominal = np.zeros(len(q))
        nominal[self._index] = q_nominal
        prog.AddQuadraticErrorCost(np.eye(len(q)), nominal, q)
        guess = np.zeros(len(q))
        guess[self._index] = seed
        prog.SetInitialGuess(q, guess)
        result = Solve(prog)
        if not result.is_success():
            return None
        solution = result.GetSolution(q)[self._index]
        if joint_limits:
            solution = np.clip(solution, self.lower, self.upper)
        return solution

    def closest_miss(self, tool: Frame, X_BE: RigidTransform, seeds: list[np.ndarray]) -> tuple[float, float]:
        """(position error m, angle error rad) of the best least-squares IK solution."""
        best = (math.inf, math.inf)
        for seed in seeds:
            ik = InverseKinematics(self._plant, with_joint_limits=True)
            base = self._plant.world_frame()
            ik.AddPositionCost(base, X_BE.translation(), tool, np.zeros(3), np.eye(3))
            ik.AddOrientationCost(base, X_BE.rotation(), tool, RotationMatrix(), 0.1)
            prog = ik.get_mutable_prog()
            guess = np.zeros(self._plant.num_positions())
            guess[self._index] = seed
            prog.SetInitialGuess(ik.q(), guess)
            result = Solve(prog)
            self._plant.SetPositions(self._context, result.GetSolution(ik.q()))
            X_BT = tool.CalcPoseInWorld(self._context)
            error = (
                float(np.linalg.norm(X_BT.translation() - X_BE.translation())),
                float(X_BT.rotation().InvertAndCompose(X_BE.rotation()).ToAngleAxis().angle()),
            )
            best = min(best, error)
        return best

    def seeds(self, q_seed: np.ndarray, count: int) -> list[np.ndarray]:
        """``q_seed``, then the arm's named poses (nearest first), then fixed random ones."""
        named = []
        for name in _SEED_POSES:
            try:
                named.append(arms.named_pose(name, self.config))
            except UnknownNameError:  # a robot without that course pose
                continue
        named.sort(key=lambda q: float(np.linalg.norm(q - q_seed)))
        rng = np.random.default_rng(0)
        seeds = [q_seed] + named
        while len(seeds) < count:
            seeds.append(rng.uniform(self.lower, self.upper))
        return seeds[: max(count, 1)]

    def wrap_into_limits(self, q: np.ndarray, q_seed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``q`` shifted by whole turns nearest ``q_seed``, then by a turn into the joint
        limits where that helps; and how far (rad) each joint is still outside them
        (<= 0: inside)."""
        wrapped = q + 2 * np.pi * np.round((q_seed - q) / (2 * np.pi))
        wrapped = np.where(wrapped > self.upper, wrapped - 2 * np.pi, wrapped)
        wrapped = np.where(wrapped < self.lower, wrapped + 2 * np.pi, wrapped)
        outside = np.maximum(wrapped - self.upper, self.lower - wrapped)
        return wrapped, outside

    def joint_limit_error(self, where: str, q: np.ndarray, outside: np.ndarray) -> UnreachableError:
        """The error for a pose reachable only outside the joint limits: the joint
        furthest ``outside`` them and its value in the solution ``q``."""
        j = int(np.argmax(outside))
        return UnreachableError(
            f"the {where} is reachable only outside the joint limits: "
            f"{arms.JOINT_NAMES[j]} would be {q[j]:.3f} rad, limits "
            f"[{self.lower[j]:.3f}, {self.upper[j]:.3f}]"
        )


def inverse_kinematics(
    kinematics: ArmKinematics,
    collision: CollisionModel | None,
    base: np.ndarray,
    X_WE: RigidTransform,
    frame: str,
    q_seed: np.ndarray,
    *,
    position_tolerance: float,
    orientation_tolerance: float,
    num_seeds: int,
) -> np.ndarray:
    """Joint positions putting tool frame E at ``X_WE``, ``usable`` (collision free),
    nearest ``q_seed``: see :meth:`ArmPlanner.ik
    <omtp_drake.control.motion.planner.ArmPlanner.ik>`.

    ``collision``: the model a solution must be collision free in (None: any
    solution is usable); ``base``: the full configuration of everything but the arm.
    """

    def usable(q: np.ndarray) -> bool:
        return collision is None or collision.config_free(collision.with_arm(base, q))

    if num_seeds < 1:
        raise ConfigError(f"num_seeds must be >= 1, got {num_seeds}")
    tool = kinematics.frame(frame)
    X_BE = kinematics.X_WB.inverse() @ RigidTransform(X_WE)
    tolerances = (position_tolerance, orientation_tolerance)
    seeds = kinematics.seeds(q_seed, num_seeds)
    solutions: list[np.ndarray] = []
    for k, seed in enumerate(seeds):
        q = kinematics.solve(tool, X_BE, seed, q_seed, *tolerances)
        if q is None:
            continue
        if k == 0 and usable(q):
            return q
        solutions.append(q)
    free = [q for q in solutions if usable(q)]
    if free:
        return min(free, key=lambda q: float(np.linalg.norm(q - q_seed)))
    where = f"{frame} pose {fmt_pose(RigidTransform(X_WE))} for {kinematics.config.name}"
    if solutions and collision is not None:
        raise collision.ik_error(where, solutions, q_seed, base)
    # Without joint limits: a solution may only need whole turns to fit in them.
    for seed in seeds[:3]:
        q = kinematics.solve(tool, X_BE, seed, q_seed, *tolerances, joint_limits=False)
        if q is None:
            continue
        wrapped, outside = kinematics.wrap_into_limits(q, q_seed)
        if np.all(outside <= 0) and usable(wrapped):
            return wrapped
        if np.any(outside > 0):
            raise kinematics.joint_limit_error(where, q, outside)
    position_error, angle_error = kinematics.closest_miss(tool, X_BE, seeds[:3])
    raise UnreachableError(
        f"unreachable: the {where}: the closest solution misses it by "
        f"{position_error * 1000:.0f} mm and {math.degrees(angle_error):.1f} deg"
    )
