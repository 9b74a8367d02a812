"""The kinematic queries of :class:`~omtp_drake.control.motion.planner.ArmPlanner`.

:class:`ArmKinematicsQueries` is the part of the planner that answers where the tool
is and how to put it somewhere: forward kinematics, IK with seeds
(:mod:`~omtp_drake.control.motion.ik`) and straight-line tool motions
(:mod:`~omtp_drake.control.motion.cartesian`), over the planner's collision model and
kinematics; with the check of the joint positions the planner is given.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell import arms
from omtp_drake.control.motion.cartesian import cartesian_path
from omtp_drake.control.motion.collision import CollisionModel, OtherPositions
from omtp_drake.control.motion.ik import ArmKinematics, inverse_kinematics
from omtp_drake.scenario import RobotConfig


class ArmKinematicsQueries:
    """Forward and inverse kinematics and Cartesian paths of one arm (a base of
    :class:`~omtp_drake.control.motion.planner.ArmPlanner`, which builds the
    collision model and the kinematics these read)."""

    _config: RobotConfig
    _collision: CollisionModel
    _kinematics: ArmKinematics

    def _q(self, q) -> np.ndarray:
        """``q`` checked (six finite joint positions within the limits), clipped to them."""
        q = arms.check_joint_positions(q, self._config)
        return np.clip(q, self._kinematics.lower, self._kinematics.upper)

    # ------------------------------------------------------------ kinematics

    def forward_kinematics(self, q, frame: str = "tip") -> RigidTransform:
        """``X_WE``: the world pose of tool frame E (``tip``, ``suction_cup``, ``tool0``) at ``q``."""
        return self._kinematics.forward_kinematics(self._q(q), frame)

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
                closest solution misses the pose) or reachable only ``outside the joint
                limits`` (UnreachableError), or every solution found is in collision
                (GoalInCollisionError, naming the bodies).
        """
        q_seed = self._q(self._collision.q_initial if q_seed is None else q_seed)
        return inverse_kinematics(
            self._kinematics,
            self._collision if check_collisions else None,
            self._collision.full(q_seed, other_q),
            X_WE,
            frame,
            q_seed,
            position_tolerance=position_tolerance,
            orientation_tolerance=orientation_tolerance,
            num_seeds=num_seeds,
        )

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
            The joint path (starting with ``q_start``) and the fraction achieved, 0...1,
            as MoveIt counts it: the waypoints reached plus the reached share of the
            segment it stopped in, over the number of waypoints (1.0: the whole motion).
        """
        q_start = self._q(q_start)
        return cartesian_path(
            self._kinematics,
            self._collision if avoid_collisions else None,
            q_start,
            waypoints,
            self._collision.full(q_start, other_q),
            frame=frame,
            max_step=max_step,
            max_rotation_step=max_rotation_step,
            jump_threshold=jump_threshold,
        )
