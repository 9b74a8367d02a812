"""moveit_commander's MoveGroupCommander on a cell's arm.

Move groups are the SRDF's (:mod:`omtp_drake.ros.moveit.config`: a student's
``--srdf``/``--moveit-config``, else the cell's own: ``robot1``, ``robot2``), each on
the arm whose six joints it moves; the planning frame is ``world``; the end-effector
link is the SRDF's (its end effector's parent link, or its chain's tip: the course's
``vacuum_gripperN_suction_cup``; ``set_end_effector_link`` takes the gripper's
``vacuum_gripperN_tip``, the cup face, or ``robotN_tool0``). Named targets are the
group's SRDF states (``R2Home``...) and the remembered joint values; the target
setters and plan options are the commander's :class:`~omtp_drake.ros.moveit.targets.MoveGroupTargets`
half.

As in MoveIt, planning and execution failures are not exceptions: ``go`` and
``execute`` return False and ``plan`` an empty trajectory (logged with the
reason); a bad argument raises MoveItCommanderException. A motion that touches
something it should not stops there (the arm's collision guard) and is recorded
in the run's report. Blocking calls advance simulated time (planning, a
trajectory's start and a Cartesian path take the session's latencies, see
:mod:`omtp_drake.ros.comm.latency`); topic callbacks run
meanwhile, between the move's steps, in time order (one at a time: a callback's
own moves run to their end before the next callback).

Plans are timed within the arm's joint limits (or ``joint_limits.yaml``'s) scaled by
the velocity and acceleration scaling factors (1.0 by default, or the file's
``default_*_scaling_factor``); Cartesian paths also keep the
tool at or below the cell's tool-speed limit for straight moves.
"""

from __future__ import annotations

import logging
import time as wall
from typing import Any, Optional

import numpy as np
from pydrake.math import RigidTransform
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.errors import (
    CollisionError,
    GoalInCollisionError,
    OmtpError,
    PlanningError,
    StartInCollisionError,
    UnreachableError,
)
from omtp_drake.ros.comm._core import (
    SETTLE_TIMEOUT,
    SETTLE_TOLERANCE,
    Plan,
    tool_frame_names,
)
from omtp_drake.ros.comm.interfaces import MoveItErrorCodes, RobotTrajectory
from omtp_drake.ros.comm.latency import delay_of, delayed, pass_time, think
from omtp_drake.ros.comm.messages import Header, Message, Pose, PoseStamped
from omtp_drake.ros.comm.rostime import Time, _blocking
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.bounds import StartStateInvalid, fix_start, with_prefix
from omtp_drake.ros.moveit.config import arm_joint_limits, end_effector_link, semantics
from omtp_drake.ros.moveit.targets import MoveGroupTargets, MoveItCommanderException
from omtp_drake.ros.moveit.trajectories import from_msg, joint_names, to_msg
from omtp_drake.ros.tf.convert import pose_msg, rigid

__all__ = ["MoveGroupCommander", "MoveItCommanderException"]

_log = logging.getLogger("moveit_commander")


def _error_code(error: PlanningError) -> int:
    """MoveIt's error code for a failed plan, by the kind of failure."""
    if isinstance(error, StartInCollisionError):
        return MoveItErrorCodes.START_STATE_IN_COLLISION
    if isinstance(error, UnreachableError):
        return MoveItErrorCodes.NO_IK_SOLUTION
    if isinstance(error, GoalInCollisionError):
        return MoveItErrorCodes.GOAL_IN_COLLISION
    return MoveItErrorCodes.PLANNING_FAILED


class MoveGroupCommander(MoveGroupTargets):
    """moveit_commander.MoveGroupCommander for ``name`` (``robot1``, ``robot2``)."""

    def __init__(
        self,
        name: str,
        robot_description: str = "robot_description",
        ns: str = "",
        wait_for_servers: float = 5.0,
    ):
        self._session = session = current()
        self._semantic = semantic = semantics(session)
        groups = semantic.move_groups()
        if name not in groups:
            raise MoveItCommanderException(f"group {name!r} was not found; groups: {', '.join(groups)}")
        self._name = name
        self._robot = robot = str(semantic.group(name).robot)
        self._arm = session.cell.arm(robot)
        self._links = {full: short for short, full in tool_frame_names(self._arm.config).items()}
        self._eef = end_effector_link(semantic, name, self._links)
        if semantic.disabled_collisions:
            self._arm.planner.filter_collisions((p[0], p[1]) for p in semantic.disabled_collisions)
        self._target: Optional[tuple[str, Any]] = None
        self._remembered: dict[str, np.ndarray] = {}
        limits = session.joint_limits
        self._velocity_scale = (limits and limits.default_velocity_scaling) or 1.0
        self._acceleration_scale = (limits and limits.default_acceleration_scaling) or 1.0
        self._motion_end = -1.0
        self._motion_goal = np.zeros(0)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"MoveGroupCommander.{name}")

    # ------------------------------------------------------------ state

    def get_name(self) -> str:
        return self._name

    def get_planning_frame(self) -> str:
        return "world"

    def get_pose_reference_frame(self) -> str:
        return "world"

    def get_end_effector_link(self) -> str:
        return self._eef

    def set_end_effector_link(self, link_name: str) -> None:
        if link_name not in self._links:
            raise MoveItCommanderException(
                f"{link_name!r} is no end-effector link of {self._name}; links: {', '.join(self._links)}"
            )
        self._eef = link_name

    def has_end_effector_link(self) -> bool:
        return True

    def get_active_joints(self) -> list[str]:
        return joint_names(self._robot)

    get_joints = get_active_joints

    def get_current_joint_values(self) -> list[float]:
        return [float(x) for x in self._arm.joint_values()]

    def get_current_pose(self, end_effector_link: str = "") -> Message:
        X_WE = self._arm.tool_pose(self._short(end_effector_link))
        return PoseStamped(Header(stamp=Time.now(), frame_id="world"), pose_msg(X_WE))

    def get_current_rpy(self, end_effector_link: str = "") -> list[float]:
        from pydrake.math import RollPitchYaw

        X_WE = self._arm.tool_pose(self._short(end_effector_link))
        return [float(x) for x in RollPitchYaw(X_WE.rotation()).vector()]

    # ------------------------------------------------------------ planning and moving

    def _plan(self, joints: Any, start: Optional[np.ndarray] = None) -> tuple[Optional[Plan], int, float]:
        """(plan or None, MoveIt's error code, wall seconds) to the target, from where the
        arm is (or ``start``), with MoveIt's start-state bounds fix (omtp_drake.ros.moveit.bounds)."""
        if joints is not None:
            if isinstance(joints, (Pose, PoseStamped)):
                self.set_pose_target(joints)
            elif isinstance(joints, str):
                self.set_named_target(joints)
            else:
                self.set_joint_value_target(joints)
        if self._target is None:
            raise MoveItCommanderException(
                f"{self._name}: no target set (set_named_target, set_pose_target...)"
            )
        kind, value = self._target
        began = wall.perf_counter()
        q_actual = self._arm.joint_values() if start is None else np.asarray(start, dtype=float)
        try:
            q_start = fix_start(self._session, self._bounds(), q_actual)
        except StartStateInvalid:
            return None, MoveItErrorCodes.START_STATE_INVALID, wall.perf_counter() - began
        try:
            if kind == "pose":
                target, frame = value
                plan = self._arm.plan(target, frame=frame, speed=self._velocity_scale, start=q_start)
            else:
                plan = self._arm.plan(value, speed=self._velocity_scale, start=q_start)
            plan = self._retime(plan)
        except PlanningError as e:
            _log.error("%s: planning failed: %s", self._name, e)
            return None, _error_code(e), wall.perf_counter() - began
        return with_prefix(plan, q_actual, q_start), MoveItErrorCodes.SUCCESS, wall.perf_counter() - began

    def _retime(self, plan: Plan) -> Plan:
        """``plan`` timed again with the acceleration scaling factor and joint_limits.yaml's
        limits (unchanged when neither applies)."""
        limits = arm_joint_limits(self._session, self._robot, self._arm.planner)
        if self._acceleration_scale >= 1.0 and limits is None:
            return plan
        velocity, acceleration = limits if limits is not None else (None, None)
        trajectory = self._arm.planner.time_parameterize(
            list(plan.path),
            velocity_scale=self._velocity_scale,
            acceleration_scale=self._acceleration_scale,
            velocity_limits=velocity,
            acceleration_limits=acceleration,
        )
        return Plan(trajectory, plan.path, plan.kind, plan.fraction)

    def plan(self, joints: Any = None) -> Any:
        """Noetic: ``(success, RobotTrajectory, planning_time, MoveItErrorCodes)``; with
        ``--moveit melodic``: the RobotTrajectory (empty when planning failed). Takes the
        session's ``plan`` latency of simulated time, which is the ``planning_time`` it
        reports (the same every run)."""
        plan, code, _seconds = self._plan(joints)
        think("plan")
        trajectory = to_msg(plan, self._robot, self._session) if plan is not None else RobotTrajectory()
        if self._session.moveit == "melodic":
            return trajectory
        return plan is not None, trajectory, delay_of("plan"), MoveItErrorCodes(code)

    def go(self, joints: Any = None, wait: bool = True) -> bool:
        """Plans and runs; the motion starts after the session's ``plan`` and ``execute``
        latencies (``wait=False`` returns at once, as MoveIt's asynchronous move)."""
        if isinstance(joints, bool):
            joints, wait = None, joints
        plan, _code, _seconds = self._plan(joints)
        if not wait:
            return plan is not None and self._run(plan, False, delay_of("plan") + delay_of("execute"))
        think("plan")
        return plan is not None and self._run(plan, wait)

    def execute(self, plan_msg: Any, wait: bool = True) -> bool:
        """Runs a plan; it starts after the session's ``execute`` latency."""
        try:
            plan = from_msg(plan_msg, self._robot, self._session)
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None
        return self._run(plan, wait)

    def _run(self, plan: Plan, wait: bool, start: Optional[float] = None) -> bool:
        """Runs ``plan`` after ``start`` seconds (None: the ``execute`` latency)."""
        session = self._session
        start = delay_of("execute") if start is None else start
        if wait:
            pass_time(start)
        else:
            plan = delayed(plan, start)
        with _blocking():
            try:
                result = self._arm.execute(plan, wait=wait)
            except CollisionError as e:
                session.collisions.append(str(e))
                _log.error("%s: execution stopped: %s", self._name, e)
                return False
            except PlanningError as e:
                _log.error("%s: execution refused: %s", self._name, e)
                return False
        self._motion_end = result.end
        self._motion_goal = plan.trajectory.value(plan.trajectory.end_time()).ravel()
        return True

    def _motion_done(self) -> bool:
        """Whether the motion started last has ended as MoveIt's execution ends: the
        trajectory over and the robot stopped (``waitForRobotToStop``), here the arm at
        the plan's goal or ``SETTLE_TIMEOUT`` after the plan's end."""
        time = self._session.time
        if time < self._motion_end - 1e-9:
            return False
        off = float(np.max(np.abs(self._arm.joint_values() - self._motion_goal)))
        return off <= SETTLE_TOLERANCE or time >= self._motion_end + SETTLE_TIMEOUT - 1e-9

    def _wait_for_motion(self, seconds: float = 0.0) -> None:
        """Advances time until :meth:`_motion_done` (at most ``seconds`` when > 0)."""
        limit = self._motion_end + SETTLE_TIMEOUT
        if seconds > 0:
            limit = min(limit, self._session.time + seconds)
        with _blocking():
            self._session.run_until(limit, until=self._motion_done)

    def stop(self) -> None:
        """Stops a motion started with ``wait=False`` where the arm is (no-op when none runs)."""
        if self._session.time < self._motion_end - 1e-9:
            q = self._arm.joint_values()
            hold = PiecewisePolynomial.FirstOrderHold([0.0, 1e-3], np.column_stack([q, q]))
            self._arm.execute(Plan(hold, (q,), "joint"), wait=False)
            self._motion_end = -1.0

    def compute_cartesian_path(
        self, waypoints: Any, eef_step: float, *args: Any, **kwargs: Any
    ) -> tuple[Message, float]:
        """``(plan, fraction)`` of straight tool moves through ``waypoints`` (Poses in world):
        MoveIt's ``(waypoints, eef_step, jump_threshold, avoid_collisions=True)`` and the
        1.1.15+ ``(waypoints, eef_step, avoid_collisions=True)``. ``avoid_collisions``
        checks the planning scene (the static cell, the other arm, added objects, the
        held part); loose parts are no obstacles, as in MoveIt's scene."""
        jump_threshold, avoid = _cartesian_args(args, kwargs)
        step = float(eef_step)
        if not step > 0:
            raise MoveItCommanderException(f"eef_step must be > 0 m, got {eef_step}")
        poses = [
            rigid(p, f"waypoint {i}") if not isinstance(p, RigidTransform) else p
            for i, p in enumerate(waypoints)
        ]
        plan = self._cartesian(poses, step, jump_threshold, avoid, self._eef, self._arm.joint_values())
        think("cartesian")
        return to_msg(plan, self._robot, self._session), float(plan.fraction)

    def _cartesian(
        self, poses: list[RigidTransform], step: float, jump: float, avoid: bool, link: str, start: np.ndarray
    ) -> Plan:
        """Straight moves of ``link`` through world ``poses`` from joint values ``start``
        (a start just outside the bounds fixed as for a plan; StartStateInvalid when farther)."""
        q_start = fix_start(self._session, self._bounds(), start)
        plan = self._arm.compute_cartesian_path(
            poses,
            step,
            jump,
            avoid,
            frame=self._links[link],
            joint_limits=arm_joint_limits(self._session, self._robot, self._arm.planner),
            start=q_start,
        )
        return with_prefix(plan, start, q_start)


def _cartesian_args(args: tuple, kwargs: dict) -> tuple[float, bool]:
    """(jump_threshold, avoid_collisions) from both compute_cartesian_path signatures."""
    rest = list(args)
    jump = kwargs.pop("jump_threshold", None)
    if rest and not isinstance(rest[0], bool) and jump is None:
        jump = rest.pop(0)
    avoid = kwargs.pop("avoid_collisions", rest.pop(0) if rest else True)
    if kwargs.pop("path_constraints", None) is not None or (rest and rest[0] is not None):
        not_supported("compute_cartesian_path with path_constraints")
    if kwargs:
        raise MoveItCommanderException(f"compute_cartesian_path got unknown arguments: {', '.join(kwargs)}")
    return float(jump or 0.0), bool(avoid)
