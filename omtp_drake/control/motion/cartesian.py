"""Straight-line tool motions, like MoveIt's ``compute_cartesian_path``: the tool
frame E moves in straight lines (rotation by slerp) through world poses, each small
step solved by IK seeded by the step before, until a step is unreachable, jumps to
another IK branch, or collides. A start in collision (a held part pressed into the
floor) may move out of it: the pairs it starts in are allowed until they have ended,
as long as no new one comes.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell.poses import interpolate_pose
from omtp_drake.control.motion.collision import CollisionModel
from omtp_drake.control.motion.formatting import fmt_pairs, fmt_pose
from omtp_drake.control.motion.ik import ArmKinematics
from omtp_drake.errors import ConfigError

_log = logging.getLogger(__name__)


def cartesian_path(
    kinematics: ArmKinematics,
    collision: CollisionModel | None,
    q_start: np.ndarray,
    waypoints: Sequence[RigidTransform],
    base: np.ndarray,
    *,
    frame: str,
    max_step: float,
    max_rotation_step: float,
    jump_threshold: float | None,
) -> tuple[list[np.ndarray], float]:
    """The joint path (from ``q_start``, already checked) of a straight-line motion of
    tool frame ``frame`` through ``waypoints`` (each an ``X_WE``), and the fraction of
    its steps achieved: see :meth:`ArmPlanner.cartesian_path
    <omtp_drake.control.motion.planner.ArmPlanner.cartesian_path>`.

    ``collision``: the model each step's joint segment is checked with (None: no
    check); ``base``: the full configuration of everything but the arm.
    """
    if max_step <= 0 or max_rotation_step <= 0:
        raise ConfigError(f"max_step and max_rotation_step must be > 0, got {max_step}, {max_rotation_step}")
    if jump_threshold is not None and jump_threshold <= 0:
        raise ConfigError(f"jump_threshold must be > 0 rad or None, got {jump_threshold}")
    tool = kinematics.frame(frame)
    targets, segments = _interpolate_poses(
        kinematics.forward_kinematics(q_start, frame),
        [RigidTransform(X) for X in waypoints],
        max_step,
        max_rotation_step,
    )
    path = [q_start]
    if not targets:
        return path, 1.0
    X_BW = kinematics.X_WB.inverse()
    leaving = set() if collision is None or collision.config_free(base) else set(collision.pairs(base))
    for X_WE in targets:
        previous = path[-1]
        q = kinematics.solve(tool, X_BW @ X_WE, previous, previous, 1e-4, 1e-3)
        reason, leaving = _why_stop(collision, base, X_WE, previous, q, jump_threshold, leaving)
        if reason is not None or q is None:
            _log.info(
                "cartesian path of %s stops after %d of %d steps: %s",
                kinematics.config.name,
                len(path) - 1,
                len(targets),
                reason,
            )
            break
        path.append(q)
    return path, _fraction(len(path) - 1, segments)


def _fraction(done: int, segments: list[int]) -> float:
    """MoveIt's fraction of a Cartesian path: the waypoints reached, plus the reached share
    of the segment it stopped in, over the number of waypoints (``done`` steps of
    ``segments``, the steps of each waypoint's segment)."""
    for i, steps in enumerate(segments):
        if done < steps:
            return (i + done / steps) / len(segments)
        done -= steps
    return 1.0


def _why_stop(
    collision: CollisionModel | None,
    base: np.ndarray,
    X_WE: RigidTransform,
    previous: np.ndarray,
    q: np.ndarray | None,
    jump_threshold: float | None,
    leaving: set[tuple[str, str]],
) -> tuple[str | None, set[tuple[str, str]]]:
    """Why the step from ``previous`` to ``q`` (the IK solution at ``X_WE``, None if
    unreachable) ends the path (None when it does not), and the start's pairs still
    being left (``leaving``: allowed until the path is free of them)."""
    if q is None:
        return f"unreachable at {fmt_pose(X_WE)}", leaving
    jump = float(np.max(np.abs(q - previous)))
    if jump_threshold is not None and jump > jump_threshold:
        return f"joint jump of {jump:.3f} rad at {fmt_pose(X_WE)}", leaving
    if collision is not None and not collision.edge_free(
        collision.with_arm(base, previous), collision.with_arm(base, q)
    ):
        pairs = collision.pairs(collision.with_arm(base, q))
        if leaving and set(pairs) <= leaving:
            # Moving out of the start's collision (free at q: out of it, after the step).
            return None, leaving if pairs else set()
        return f"collision at {fmt_pose(X_WE)}: {fmt_pairs(pairs) or 'on the way'}", leaving
    return None, set()


def _interpolate_poses(
    X_start: RigidTransform, waypoints: list[RigidTransform], max_step: float, max_rotation_step: float
) -> tuple[list[RigidTransform], list[int]]:
    """Poses along straight lines (slerped rotations) through ``waypoints``, at most
    ``max_step`` m and ``max_rotation_step`` rad apart, ``X_start`` excluded; and how many
    of them each waypoint's segment has."""
    poses: list[RigidTransform] = []
    segments: list[int] = []
    previous = X_start
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
        segments.append(steps)
        previous = X
    return poses, segments
