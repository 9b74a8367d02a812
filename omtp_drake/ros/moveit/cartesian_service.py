"""MoveIt's ``/compute_cartesian_path`` service (``moveit_msgs/GetCartesianPath``) on the
cell's planner.

As move_group's Cartesian path capability: ``link_name`` (default: the group's
end-effector link, the course's ``vacuum_gripperN_suction_cup``) moves in straight
lines through ``waypoints`` (poses in ``header.frame_id``: empty, ``world`` or the
link itself mean world; another tf frame is resolved at the latest time) from
``start_state`` (where the arm is, with the joints it names set), in steps of at
most ``max_step`` m; ``avoid_collisions`` checks the planning scene. The answer
is the ``solution`` RobotTrajectory (executable with ``execute_trajectory``), the
``fraction`` of the path achieved and the error code: SUCCESS (also for a partial
path or no waypoints), FAILURE (``max_step`` not > 0, an unknown link),
FRAME_TRANSFORM_FAILURE, INVALID_GROUP_NAME. The path, its timing and its
``jump_threshold`` are the commander's ``compute_cartesian_path`` (which calls
this service in MoveIt); path constraints and a Cartesian speed limit are not
supported. The computation takes the session's ``cartesian`` latency.
"""

from __future__ import annotations

import logging
from typing import Any

from pydrake.math import RigidTransform

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm._core import CorePoseStamped
from omtp_drake.ros.comm.interfaces import MoveItErrorCodes, RobotState
from omtp_drake.ros.comm.latency import think
from omtp_drake.ros.comm.messages import Header, JointState, Message, Time
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.bounds import StartStateInvalid
from omtp_drake.ros.moveit.commander import MoveGroupCommander
from omtp_drake.ros.moveit.config import semantics
from omtp_drake.ros.moveit.interfaces import GetCartesianPathResponse
from omtp_drake.ros.moveit.move_group import start_joints
from omtp_drake.ros.moveit.trajectories import joint_names, to_msg
from omtp_drake.ros.tf.convert import rigid

_log = logging.getLogger("moveit_commander")


def _waypoints(request: Any, link: str) -> list[RigidTransform]:
    """The request's waypoints in world (OmtpError when tf cannot resolve their frame)."""
    frame = request.header.frame_id.lstrip("/")
    poses = [rigid(p, f"waypoint {i}") for i, p in enumerate(request.waypoints)]
    if frame in ("", "world", link):
        return poses
    cell = current().cell
    stamp = request.header.stamp.to_sec() or None
    return [cell.world_pose(CorePoseStamped(frame, stamp, X)) for X in poses]


def _failure(response: Any, code: int, why: str) -> Any:
    _log.error("compute_cartesian_path: %s", why)
    response.error_code = MoveItErrorCodes(code)
    return response


def compute_cartesian_path(request: Any) -> Message:
    """The ``/compute_cartesian_path`` handler (see the module doc)."""
    session = current()
    response: Any = GetCartesianPathResponse()
    groups = semantics(session).move_groups()
    if request.group_name not in groups:
        why = f"group {request.group_name!r} was not found; groups: {', '.join(groups)}"
        return _failure(response, MoveItErrorCodes.INVALID_GROUP_NAME, why)
    if request.path_constraints.joint_constraints or request.path_constraints.position_constraints:
        not_supported("/compute_cartesian_path with path_constraints")
    group = MoveGroupCommander(request.group_name)
    link = request.link_name or group.get_end_effector_link()
    if link not in group._links:
        why = f"Unknown frame: {link}; the links of {group.get_name()}: {', '.join(group._links)}"
        return _failure(response, MoveItErrorCodes.FAILURE, why)
    try:
        poses = _waypoints(request, link)
    except OmtpError as e:
        return _failure(response, MoveItErrorCodes.FRAME_TRANSFORM_FAILURE, str(e))
    if not request.max_step > 0:
        why = f"the maximum step between configurations must be > 0 m, got {request.max_step}"
        return _failure(response, MoveItErrorCodes.FAILURE, why)
    q_start = start_joints(session.cell, group._robot, request.start_state)
    names = joint_names(group._robot)
    state = JointState(
        header=Header(stamp=Time(session.time)), name=names, position=[float(x) for x in q_start]
    )
    response.start_state = RobotState(joint_state=state)
    if poses:
        try:
            plan = group._cartesian(
                poses,
                float(request.max_step),
                float(request.jump_threshold),
                bool(request.avoid_collisions),
                link,
                q_start,
            )
        except StartStateInvalid as e:
            return _failure(response, MoveItErrorCodes.START_STATE_INVALID, str(e))
        except OmtpError as e:
            return _failure(response, MoveItErrorCodes.FAILURE, str(e))
        think("cartesian")
        response.solution = to_msg(plan, group._robot, session)
        response.fraction = float(plan.fraction)
    response.error_code = MoveItErrorCodes(MoveItErrorCodes.SUCCESS)
    return response
