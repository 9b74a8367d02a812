"""The course cell's own ROS interfaces: omtp_gazebo, std_srvs and moveit_msgs types.

Messages follow the course's ``rosmsg show`` output (see
``shared/reference/omtp_factory.md`` section 9); services have a request and a
response class each, and the service class names both (``_request_class``,
``_response_class``) as genpy's do.
"""

from __future__ import annotations

from typing import ClassVar

from omtp_drake.ros.comm.messages import (
    Header,
    JointState,
    JointTrajectory,
    Message,
    Pose,
)


class ServiceType:
    """A service: its request and response message classes."""

    _type: ClassVar[str] = ""
    _request_class: ClassVar[type[Message]]
    _response_class: ClassVar[type[Message]]


# ----------------------------------------------------------------------------- omtp_gazebo


class Model(Message):
    """One model a logical camera sees: its type and its pose in the camera frame."""

    __slots__ = ("type", "pose")
    _type = "omtp_gazebo/Model"
    _defaults = (str, Pose)


class LogicalCameraImage(Message):
    """What a logical camera sees (no header: scripts stamp it themselves)."""

    __slots__ = ("models", "pose")
    _type = "omtp_gazebo/LogicalCameraImage"
    _defaults = (list, Pose)


class ConveyorBeltState(Message):
    __slots__ = ("power",)
    _type = "omtp_gazebo/ConveyorBeltState"
    _defaults = (float,)


class VacuumGripperState(Message):
    __slots__ = ("enabled", "attached")
    _type = "omtp_gazebo/VacuumGripperState"
    _defaults = (bool, bool)


class Proximity(Message):
    """The break beam's state (the proximity-ray plugin's message): whether something
    is in the beam's range, and that range's limits (m)."""

    __slots__ = ("header", "object_detected", "min_range", "max_range")
    _type = "omtp_gazebo/Proximity"
    _defaults = (Header, bool, float, float)


class VacuumGripperControlRequest(Message):
    __slots__ = ("enable",)
    _type = "omtp_gazebo/VacuumGripperControlRequest"
    _defaults = (bool,)


class VacuumGripperControlResponse(Message):
    __slots__ = ("success",)
    _type = "omtp_gazebo/VacuumGripperControlResponse"
    _defaults = (bool,)


class VacuumGripperControl(ServiceType):
    _type = "omtp_gazebo/VacuumGripperControl"
    _request_class = VacuumGripperControlRequest
    _response_class = VacuumGripperControlResponse


class ConveyorBeltControlRequest(Message):
    __slots__ = ("state",)
    _type = "omtp_gazebo/ConveyorBeltControlRequest"
    _defaults = (ConveyorBeltState,)


class ConveyorBeltControlResponse(Message):
    __slots__ = ("success",)
    _type = "omtp_gazebo/ConveyorBeltControlResponse"
    _defaults = (bool,)


class ConveyorBeltControl(ServiceType):
    _type = "omtp_gazebo/ConveyorBeltControl"
    _request_class = ConveyorBeltControlRequest
    _response_class = ConveyorBeltControlResponse


# ----------------------------------------------------------------------------- std_srvs


class EmptyRequest(Message):
    __slots__ = ()
    _type = "std_srvs/EmptyRequest"


class EmptyResponse(Message):
    __slots__ = ()
    _type = "std_srvs/EmptyResponse"


class EmptyService(ServiceType):
    _type = "std_srvs/Empty"
    _request_class = EmptyRequest
    _response_class = EmptyResponse


class TriggerRequest(Message):
    __slots__ = ()
    _type = "std_srvs/TriggerRequest"


class TriggerResponse(Message):
    __slots__ = ("success", "message")
    _type = "std_srvs/TriggerResponse"
    _defaults = (bool, str)


class Trigger(ServiceType):
    _type = "std_srvs/Trigger"
    _request_class = TriggerRequest
    _response_class = TriggerResponse


class SetBoolRequest(Message):
    __slots__ = ("data",)
    _type = "std_srvs/SetBoolRequest"
    _defaults = (bool,)


class SetBoolResponse(Message):
    __slots__ = ("success", "message")
    _type = "std_srvs/SetBoolResponse"
    _defaults = (bool, str)


class SetBool(ServiceType):
    _type = "std_srvs/SetBool"
    _request_class = SetBoolRequest
    _response_class = SetBoolResponse


# ----------------------------------------------------------------------------- moveit_msgs


class MoveItErrorCodes(Message):
    __slots__ = ("val",)
    _type = "moveit_msgs/MoveItErrorCodes"
    _defaults = (int,)
    SUCCESS: ClassVar[int] = 1
    FAILURE: ClassVar[int] = 99999
    PLANNING_FAILED: ClassVar[int] = -1
    INVALID_MOTION_PLAN: ClassVar[int] = -2
    MOTION_PLAN_INVALIDATED_BY_ENVIRONMENT_CHANGE: ClassVar[int] = -3
    CONTROL_FAILED: ClassVar[int] = -4
    UNABLE_TO_AQUIRE_SENSOR_DATA: ClassVar[int] = -5
    TIMED_OUT: ClassVar[int] = -6
    PREEMPTED: ClassVar[int] = -7
    START_STATE_IN_COLLISION: ClassVar[int] = -10
    START_STATE_VIOLATES_PATH_CONSTRAINTS: ClassVar[int] = -11
    START_STATE_INVALID: ClassVar[int] = -26
    GOAL_IN_COLLISION: ClassVar[int] = -12
    GOAL_VIOLATES_PATH_CONSTRAINTS: ClassVar[int] = -13
    GOAL_CONSTRAINTS_VIOLATED: ClassVar[int] = -14
    GOAL_STATE_INVALID: ClassVar[int] = -27
    UNRECOGNIZED_GOAL_TYPE: ClassVar[int] = -28
    INVALID_GROUP_NAME: ClassVar[int] = -15
    INVALID_GOAL_CONSTRAINTS: ClassVar[int] = -16
    INVALID_ROBOT_STATE: ClassVar[int] = -17
    INVALID_LINK_NAME: ClassVar[int] = -18
    INVALID_OBJECT_NAME: ClassVar[int] = -19
    FRAME_TRANSFORM_FAILURE: ClassVar[int] = -21
    COLLISION_CHECKING_UNAVAILABLE: ClassVar[int] = -22
    ROBOT_STATE_STALE: ClassVar[int] = -23
    SENSOR_INFO_STALE: ClassVar[int] = -24
    COMMUNICATION_FAILURE: ClassVar[int] = -25
    CRASH: ClassVar[int] = -29
    ABORT: ClassVar[int] = -30
    NO_IK_SOLUTION: ClassVar[int] = -31


class RobotTrajectory(Message):
    """A planned motion: its joint trajectory (multi-DOF part unused)."""

    __slots__ = ("joint_trajectory", "multi_dof_joint_trajectory")
    _type = "moveit_msgs/RobotTrajectory"
    _defaults = (JointTrajectory, JointTrajectory)


class RobotState(Message):
    __slots__ = ("joint_state", "is_diff")
    _type = "moveit_msgs/RobotState"
    _defaults = (JointState, bool)


class SolidPrimitive(Message):
    __slots__ = ("type", "dimensions")
    _type = "shape_msgs/SolidPrimitive"
    _defaults = (int, list)
    BOX: ClassVar[int] = 1
    SPHERE: ClassVar[int] = 2
    CYLINDER: ClassVar[int] = 3
    CONE: ClassVar[int] = 4
    BOX_X: ClassVar[int] = 0
    BOX_Y: ClassVar[int] = 1
    BOX_Z: ClassVar[int] = 2
    SPHERE_RADIUS: ClassVar[int] = 0


class CollisionObject(Message):
    """A box of the planning scene (``primitives[0]``, at ``primitive_poses[0]`` in
    ``header.frame_id``: ``world``, or the gripper's cup body when attached)."""

    __slots__ = ("header", "id", "primitives", "primitive_poses", "operation")
    _type = "moveit_msgs/CollisionObject"
    _defaults = (Header, str, list, list, int)
    ADD: ClassVar[int] = 0
    REMOVE: ClassVar[int] = 1
    APPEND: ClassVar[int] = 2
    MOVE: ClassVar[int] = 3


class AttachedCollisionObject(Message):
    __slots__ = ("link_name", "object", "touch_links", "weight")
    _type = "moveit_msgs/AttachedCollisionObject"
    _defaults = (str, CollisionObject, list, float)


class DisplayTrajectory(Message):
    __slots__ = ("model_id", "trajectory", "trajectory_start")
    _type = "moveit_msgs/DisplayTrajectory"
    _defaults = (str, list, RobotState)


class ExecuteTrajectoryGoal(Message):
    __slots__ = ("trajectory",)
    _type = "moveit_msgs/ExecuteTrajectoryGoal"
    _defaults = (RobotTrajectory,)


class ExecuteTrajectoryResult(Message):
    __slots__ = ("error_code",)
    _type = "moveit_msgs/ExecuteTrajectoryResult"
    _defaults = (MoveItErrorCodes,)


class ExecuteTrajectoryFeedback(Message):
    __slots__ = ("state",)
    _type = "moveit_msgs/ExecuteTrajectoryFeedback"
    _defaults = (str,)


class ExecuteTrajectoryAction(Message):
    """The action type: ``SimpleActionClient('execute_trajectory', ExecuteTrajectoryAction)``."""

    __slots__ = ()
    _type = "moveit_msgs/ExecuteTrajectoryAction"
    _goal_class: ClassVar[type[Message]] = ExecuteTrajectoryGoal
    _result_class: ClassVar[type[Message]] = ExecuteTrajectoryResult
