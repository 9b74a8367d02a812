"""MoveIt's ``/compute_fk`` service (``moveit_msgs/GetPositionFK``) on the cell's model.

As move_group's kinematics capability: the robot state is the cell's current one
with the joints the request's ``robot_state`` names set to its values (any joint of
the cell's URDF; values outside the joint bounds are fine, FK does not check them),
and each link of ``fk_link_names`` (any link of ``/robot_description``:
``vacuum_gripper1_suction_cup``, ``robot1_tool0``...) gets its pose in ``world``,
or in ``header.frame_id`` (any tf frame, at the latest time) when given. An
unknown link is left out (INVALID_LINK_NAME), no link at all is INVALID_LINK_NAME,
a frame tf cannot resolve is FRAME_TRANSFORM_FAILURE (the poses stay in world); a
joint the cell does not have fails the call (rospy's ServiceException), as
MoveIt's model refuses it. The call takes no simulated time beyond the service's.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

from pydrake.math import RigidTransform

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm._core import CorePoseStamped
from omtp_drake.ros.comm.interfaces import MoveItErrorCodes
from omtp_drake.ros.comm.messages import Header, Message, PoseStamped, Time
from omtp_drake.ros.gazebo.cell_services import ServiceFailure
from omtp_drake.ros.moveit.interfaces import GetPositionFKResponse
from omtp_drake.ros.tf.convert import pose_msg

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

_log = logging.getLogger("moveit_commander")


def _context_at(cell: Cell, joint_state: Any) -> Any:
    """A scratch context of the cell's plant: its state now, with the named joints set."""
    plant = cell.station.plant
    live = plant.GetMyContextFromRoot(cell.runtime.context)
    scratch = plant.CreateDefaultContext()
    q = plant.GetPositions(live).copy()
    if len(joint_state.name) != len(joint_state.position):
        _log.error("Different number of names and positions in JointState message: start state ignored")
    else:
        for name, value in zip(joint_state.name, joint_state.position):
            if not plant.HasJointNamed(name) or plant.GetJointByName(name).num_positions() != 1:
                raise ServiceFailure(f"Variable '{name}' is not known to the cell's robot model")
            q[plant.GetJointByName(name).position_start()] = float(value)
    plant.SetPositions(scratch, q)
    return scratch


def _frame_pose(cell: Cell, frame: str) -> RigidTransform:
    """``X_WF`` of tf frame ``frame`` now (OmtpError when tf has no such frame)."""
    return cell.world_pose(CorePoseStamped(frame, None, RigidTransform()))


def compute_fk(cell: Cell, request: Any) -> Message:
    """The ``/compute_fk`` handler (see the module doc)."""
    response: Any = GetPositionFKResponse()
    if not request.fk_link_names:
        _log.error("No links specified for FK request")
        response.error_code = MoveItErrorCodes(MoveItErrorCodes.INVALID_LINK_NAME)
        return response
    plant = cell.station.plant
    context = _context_at(cell, request.robot_state.joint_state)
    frame = request.header.frame_id.lstrip("/")
    X_FW, out_frame = RigidTransform(), "world"
    transform_failed = False
    if frame and frame != "world":
        try:
            X_FW, out_frame = _frame_pose(cell, frame).inverse(), frame
        except OmtpError as e:
            _log.error("compute_fk: no transform to %r: %s", frame, e)
            transform_failed = True
    for link in request.fk_link_names:
        if not plant.HasFrameNamed(link):
            continue
        X_WL = plant.GetFrameByName(link).CalcPoseInWorld(context)
        header = Header(stamp=Time(cell.time), frame_id=out_frame)
        response.pose_stamped.append(PoseStamped(header=header, pose=pose_msg(X_FW @ X_WL)))
        response.fk_link_names.append(link)
    if transform_failed:
        code = MoveItErrorCodes.FRAME_TRANSFORM_FAILURE
    elif len(response.fk_link_names) == len(request.fk_link_names):
        code = MoveItErrorCodes.SUCCESS
    else:
        code = MoveItErrorCodes.INVALID_LINK_NAME
    response.error_code = MoveItErrorCodes(code)
    return response
