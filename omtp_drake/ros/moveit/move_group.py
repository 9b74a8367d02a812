"""MoveIt's ``/move_group`` action on the cell's planner
(``/compute_ik``: :mod:`omtp_drake.ros.moveit.ik_service`).

``/move_group`` (``moveit_msgs/MoveGroupAction``): the goal's ``request`` names
the group (``robot1``, ``robot2``) and one set of goal constraints: joint
constraints (any subset of the group's joints; the others keep their current
value) or a position constraint (the region's first primitive pose) with an
orientation constraint for one link (the group's end-effector links, as
``MoveGroupCommander.set_pose_target``). ``max_velocity_scaling_factor`` and
``max_acceleration_scaling_factor`` scale the timing (0 means 1, as in MoveIt).
The plan is the same :class:`~omtp_drake.ros.moveit.commander.MoveGroupCommander` plan
scripts get; with ``planning_options.plan_only`` the result comes at once with
the planned trajectory, otherwise the arm executes it and the result comes when
the motion has ended (``executed_trajectory`` = the planned one). The plan starts
from the request's ``start_state`` (where the arm is, with the joints it names set;
a plan that does not start where the arm is cannot be executed: CONTROL_FAILED).
Joint bounds are MoveIt's (:mod:`omtp_drake.ros.moveit.bounds`: a start just outside
them is fixed, joint goals beyond them are put on them). Failures are
error codes, as in MoveIt: PLANNING_FAILED, NO_IK_SOLUTION, GOAL_IN_COLLISION,
START_STATE_IN_COLLISION, START_STATE_INVALID (outside the bounds by more than the
bounds error), INVALID_GROUP_NAME, INVALID_GOAL_CONSTRAINTS (no or
several constraint sets, a link that is no end effector, a negative tolerance),
PREEMPTED (cancelled).
Planning takes no simulated time.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm.interfaces import MoveItErrorCodes, RobotState
from omtp_drake.ros.comm.latency import delay_of
from omtp_drake.ros.comm.messages import Header, JointState, Message, Pose, PoseStamped
from omtp_drake.ros.comm.rostime import Time
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.moveit.bounds import goal_joints
from omtp_drake.ros.moveit.commander import MoveGroupCommander, MoveItCommanderException
from omtp_drake.ros.moveit.config import semantics
from omtp_drake.ros.moveit.interfaces import MoveGroupAction, MoveGroupResult
from omtp_drake.ros.moveit.trajectories import joint_names, to_msg

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

_log = logging.getLogger("moveit_commander")

#: The action servers by name (MoveIt's default namespace and the absolute name).
MOVE_GROUP_NAMES = ("move_group", "/move_group")


class GoalState:
    """actionlib_msgs/GoalStatus values the clients report."""

    PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED, LOST = 0, 1, 2, 3, 4, 5, 9


def start_joints(cell: Cell, robot: str, state: Any) -> np.ndarray:
    """The arm's joint values a request starts from: where it is, with the joints a
    ``moveit_msgs/RobotState`` names set to its values (MoveIt's start state; a joint
    state whose names and positions differ in number is ignored, as MoveIt does)."""
    q = np.array(cell.arm(robot).joint_values(), dtype=float)
    joint_state = state.joint_state
    if len(joint_state.name) != len(joint_state.position):
        _log.error("Different number of names and positions in JointState message: start state ignored")
        return q
    given = dict(zip(joint_state.name, joint_state.position))
    for i, name in enumerate(joint_names(robot)):
        if name in given:
            q[i] = float(given[name])
    return q


def _robot_state(robot: str, q: np.ndarray) -> Message:
    names = joint_names(robot)
    position = [float(x) for x in q]
    return RobotState(joint_state=JointState(header=Header(stamp=Time.now()), name=names, position=position))


def _pose_target(constraints: Any) -> tuple[Message, str]:
    """(target pose, link) of one position + orientation constraint pair."""
    position = constraints.position_constraints[0]
    region = position.constraint_region
    if not region.primitive_poses:
        raise MoveItCommanderException("the position constraint's constraint_region has no primitive pose")
    pose: Any = Pose(position=region.primitive_poses[0].position)
    if constraints.orientation_constraints:
        pose.orientation = constraints.orientation_constraints[0].orientation
    else:
        raise MoveItCommanderException("a position constraint needs an orientation constraint here")
    return PoseStamped(header=position.header, pose=pose), position.link_name


def set_goal(group: MoveGroupCommander, request: Any) -> None:
    """The goal constraints of a MotionPlanRequest as the commander's target."""
    if len(request.goal_constraints) != 1:
        raise MoveItCommanderException(
            f"the request has {len(request.goal_constraints)} goal constraint sets; the cell plans to one"
        )
    constraints = request.goal_constraints[0]
    if constraints.joint_constraints:
        try:
            goal = goal_joints(group._session, group._bounds(), constraints.joint_constraints)
        except ValueError as e:
            raise MoveItCommanderException(str(e)) from None
        group.set_joint_value_target(goal)
    elif constraints.position_constraints:
        pose, link = _pose_target(constraints)
        group.set_pose_target(pose, link)
    else:
        raise MoveItCommanderException("the goal constraints have no joint or position constraint")


class MoveGroupClient:
    """An actionlib ``SimpleActionClient`` of ``/move_group`` (see the module doc)."""

    def __init__(self, ns: str = "move_group"):
        self._session = current()
        self._state = GoalState.LOST
        self._result: Any = None
        self._end = 0.0
        self._group: Optional[MoveGroupCommander] = None
        self._done_cb: Any = None

    def wait_for_server(self, timeout: Any = None) -> bool:
        return True

    def send_goal(
        self, goal: Any, done_cb: Any = None, active_cb: Any = None, feedback_cb: Any = None
    ) -> None:
        request = goal.request
        cell = self._session.cell
        result: Any = MoveGroupResult()
        self._done_cb, self._end = done_cb, self._session.time
        groups = semantics(self._session).move_groups()
        if request.group_name not in groups:
            _log.error("move_group: group %r was not found; groups: %s", request.group_name, groups)
            self._finish(result, MoveItErrorCodes.INVALID_GROUP_NAME, GoalState.ABORTED)
            return
        self._group = group = MoveGroupCommander(request.group_name)
        q_start = start_joints(cell, group._robot, request.start_state)
        result.trajectory_start = _robot_state(group._robot, q_start)
        try:
            group.set_max_velocity_scaling_factor(request.max_velocity_scaling_factor or 1.0)
            group.set_max_acceleration_scaling_factor(request.max_acceleration_scaling_factor or 1.0)
            set_goal(group, request)
        except (MoveItCommanderException, OmtpError) as e:
            _log.error("move_group: invalid goal: %s", e)
            self._finish(result, MoveItErrorCodes.INVALID_GOAL_CONSTRAINTS, GoalState.ABORTED)
            return
        plan, code, _seconds = group._plan(None, start=q_start)
        result.planning_time = delay_of("plan")  # the session's planning latency, as go() takes it
        if plan is None:
            self._finish(result, code, GoalState.ABORTED)
            return
        result.planned_trajectory = to_msg(plan, group._robot, self._session)
        if goal.planning_options.plan_only:
            self._finish(result, MoveItErrorCodes.SUCCESS, GoalState.SUCCEEDED)
            return
        if not group._run(plan, wait=False, start=delay_of("plan") + delay_of("execute")):
            self._finish(result, MoveItErrorCodes.CONTROL_FAILED, GoalState.ABORTED)
            return
        result.executed_trajectory = result.planned_trajectory
        result.error_code = MoveItErrorCodes(MoveItErrorCodes.SUCCESS)
        self._result, self._state, self._end = result, GoalState.ACTIVE, group._motion_end
        if active_cb is not None:
            active_cb()

    def _finish(self, result: Any, code: int, state: int) -> None:
        result.error_code = MoveItErrorCodes(code)
        self._result, self._state = result, state
        if self._done_cb is not None:
            self._done_cb(state, result)

    def _poll(self) -> None:
        if self._state == GoalState.ACTIVE and self._group is not None and self._group._motion_done():
            self._state = GoalState.SUCCEEDED
            if self._done_cb is not None and self._result is not None:
                self._done_cb(self._state, self._result)

    def is_done(self) -> bool:
        self._poll()
        return self._state not in (GoalState.ACTIVE, GoalState.PENDING, GoalState.LOST)

    def wait_for_result(self, timeout: Any = None) -> bool:
        seconds = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
        if self._state == GoalState.ACTIVE and self._group is not None:
            self._group._wait_for_motion(seconds)
        return self.is_done()

    def get_state(self) -> int:
        self._poll()
        return self._state

    def get_result(self) -> Optional[Message]:
        self._poll()
        return self._result if self.is_done() else None

    def get_goal_status_text(self) -> str:
        return {GoalState.SUCCEEDED: "Solution was found and executed.", GoalState.ACTIVE: "executing"}.get(
            self.get_state(), "" if self._result is None else f"error code {self._result.error_code.val}"
        )

    def cancel_goal(self) -> None:
        if self._group is not None and self._state == GoalState.ACTIVE:
            self._group.stop()
            if self._result is not None:
                self._result.error_code = MoveItErrorCodes(MoveItErrorCodes.PREEMPTED)
            self._state = GoalState.PREEMPTED

    cancel_all_goals = cancel_goal


def is_move_group(ns: str, spec: Any) -> bool:
    return spec is MoveGroupAction and ns.strip("/") == "move_group"
