"""MoveIt's ``/compute_ik`` service (``moveit_msgs/GetPositionIK``) on the cell's planner.

The joint values putting ``ik_link_name`` (default: the group's
``vacuum_gripperN_suction_cup``) at ``pose_stamped`` (any tf frame), nearest the
request's robot state, collision free with ``avoid_collisions`` (the planning
scene: the static cell, the other arm, added objects; loose parts are no
obstacles). The solution's joint state lists the group's joints; failures answer
NO_IK_SOLUTION (or GOAL_IN_COLLISION, INVALID_GROUP_NAME, INVALID_GOAL_CONSTRAINTS
for a link that is no end effector). The call takes no simulated time.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

import numpy as np

from omtp_drake.errors import GoalInCollisionError, PlanningError
from omtp_drake.ros.comm._core import JOINT_NAMES, CorePoseStamped, other_arm_positions, tool_frame_names
from omtp_drake.ros.comm.interfaces import MoveItErrorCodes, RobotState
from omtp_drake.ros.comm.messages import Header, JointState, Message, Time
from omtp_drake.ros.moveit.interfaces import GetPositionIKResponse
from omtp_drake.ros.tf.convert import rigid

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

_log = logging.getLogger("moveit_commander")


def _joint_names(robot: str) -> list[str]:
    return [f"{robot}_{name}" for name in JOINT_NAMES]


def _ik_seed(cell: Cell, robot: str, joint_state: Message) -> np.ndarray:
    """Where the arm is, with the request's joints set; within the joint bounds (a seed only:
    MoveIt's solvers start from it wherever it is, a wrist measured a hair beyond pi too)."""
    arm = cell.arm(robot)
    q = np.array(arm.joint_values(), dtype=float)
    given = dict(zip(joint_state.name, joint_state.position))
    for i, name in enumerate(_joint_names(robot)):
        if name in given:
            q[i] = float(given[name])
    limits = arm.config.limits()
    return np.clip(q, -limits, limits)


def _ik_target(cell: Cell, pose: Message) -> Any:
    X = rigid(pose.pose, "compute_ik pose_stamped")
    frame = pose.header.frame_id.lstrip("/") or "world"
    if frame == "world":
        return X
    stamp = pose.header.stamp.to_sec()
    return cell.world_pose(CorePoseStamped(frame, stamp or None, X))


def _ik_error_code(error: PlanningError) -> int:
    """MoveIt's code for a failed IK: every solution in collision, or none found."""
    if isinstance(error, GoalInCollisionError):
        return MoveItErrorCodes.GOAL_IN_COLLISION
    return MoveItErrorCodes.NO_IK_SOLUTION


def compute_ik(cell: Cell, request: Any) -> Message:
    """The ``/compute_ik`` handler (see the module doc)."""
    ik = request.ik_request
    response: Any = GetPositionIKResponse()
    if ik.group_name not in cell.station.arms:
        _log.error("compute_ik: group %r was not found; groups: %s", ik.group_name, list(cell.station.arms))
        response.error_code = MoveItErrorCodes(MoveItErrorCodes.INVALID_GROUP_NAME)
        return response
    arm = cell.arm(ik.group_name)
    links = {full: short for short, full in tool_frame_names(arm.config).items()}
    link = ik.ik_link_name or next(f for f, s in links.items() if s == "suction_cup")
    if link not in links:
        _log.error(
            "compute_ik: %r is no end-effector link of %s; links: %s", link, ik.group_name, list(links)
        )
        response.error_code = MoveItErrorCodes(MoveItErrorCodes.INVALID_GOAL_CONSTRAINTS)
        return response
    try:
        X_WE = _ik_target(cell, ik.pose_stamped)
        q = arm._planning_scene().ik(
            X_WE,
            frame=links[link],
            q_seed=_ik_seed(cell, ik.group_name, ik.robot_state.joint_state),
            other_q=other_arm_positions(cell.runtime, arm.name),
            check_collisions=bool(ik.avoid_collisions),
        )
    except PlanningError as e:
        _log.warning("compute_ik: %s", e)
        response.error_code = MoveItErrorCodes(_ik_error_code(e))
        return response
    state = JointState(
        header=Header(stamp=Time(cell.time), frame_id="world"),
        name=_joint_names(ik.group_name),
        position=[float(x) for x in q],
    )
    response.solution = RobotState(joint_state=state)
    response.error_code = MoveItErrorCodes(MoveItErrorCodes.SUCCESS)
    return response
