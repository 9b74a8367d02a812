"""The course cell's own ROS interfaces: omtp_gazebo, std_srvs and moveit_msgs types,
declared from their ``.msg`` / ``.srv`` / ``.action`` text (:mod:`omtp_drake.ros.comm.messages`'s
factory).

Messages follow the course's ``rosmsg show`` output (see
``shared/reference/omtp_factory.md`` section 9); services have a request and a
response class each, and the service class names both (``_request_class``,
``_response_class``) as genpy's do.
"""

from __future__ import annotations

from omtp_drake.ros.comm.messages import Message, ServiceType, action, message, service

__all__ = ["Message", "ServiceType"]

# ----------------------------------------------------------------------------- omtp_gazebo

Model = message(
    "omtp_gazebo/Model",
    "string type\ngeometry_msgs/Pose pose",
    "One model a logical camera sees: its type and its pose in the camera frame.",
)
LogicalCameraImage = message(
    "omtp_gazebo/LogicalCameraImage",
    "Model[] models\ngeometry_msgs/Pose pose",
    "What a logical camera sees (no header: scripts stamp it themselves).",
)
ConveyorBeltState = message("omtp_gazebo/ConveyorBeltState", "float64 power")
VacuumGripperState = message("omtp_gazebo/VacuumGripperState", "bool enabled\nbool attached")
Proximity = message(
    "omtp_gazebo/Proximity",
    "Header header\nbool object_detected\nfloat32 min_range\nfloat32 max_range",
    "The break beam's state (the proximity-ray plugin's message): whether something is in the "
    "beam's range, and that range's limits (m).",
)
VacuumGripperControl, VacuumGripperControlRequest, VacuumGripperControlResponse = service(
    "omtp_gazebo/VacuumGripperControl", "bool enable\n---\nbool success"
)
ConveyorBeltControl, ConveyorBeltControlRequest, ConveyorBeltControlResponse = service(
    "omtp_gazebo/ConveyorBeltControl", "ConveyorBeltState state\n---\nbool success"
)

# ----------------------------------------------------------------------------- std_srvs

EmptyService, EmptyRequest, EmptyResponse = service("std_srvs/Empty", "---")
Trigger, TriggerRequest, TriggerResponse = service("std_srvs/Trigger", "---\nbool success\nstring message")
SetBool, SetBoolRequest, SetBoolResponse = service(
    "std_srvs/SetBool", "bool data\n---\nbool success\nstring message"
)

# ----------------------------------------------------------------------------- moveit_msgs

MoveItErrorCodes = message(
    "moveit_msgs/MoveItErrorCodes",
    """
    int32 val
    int32 SUCCESS=1
    int32 FAILURE=99999
    int32 PLANNING_FAILED=-1
    int32 INVALID_MOTION_PLAN=-2
    int32 MOTION_PLAN_INVALIDATED_BY_ENVIRONMENT_CHANGE=-3
    int32 CONTROL_FAILED=-4
    int32 UNABLE_TO_AQUIRE_SENSOR_DATA=-5
    int32 TIMED_OUT=-6
    int32 PREEMPTED=-7
    int32 START_STATE_IN_COLLISION=-10
    int32 START_STATE_VIOLATES_PATH_CONSTRAINTS=-11
    int32 START_STATE_INVALID=-26
    int32 GOAL_IN_COLLISION=-12
    int32 GOAL_VIOLATES_PATH_CONSTRAINTS=-13
    int32 GOAL_CONSTRAINTS_VIOLATED=-14
    int32 GOAL_STATE_INVALID=-27
    int32 UNRECOGNIZED_GOAL_TYPE=-28
    int32 INVALID_GROUP_NAME=-15
    int32 INVALID_GOAL_CONSTRAINTS=-16
    int32 INVALID_ROBOT_STATE=-17
    int32 INVALID_LINK_NAME=-18
    int32 INVALID_OBJECT_NAME=-19
    int32 FRAME_TRANSFORM_FAILURE=-21
    int32 COLLISION_CHECKING_UNAVAILABLE=-22
    int32 ROBOT_STATE_STALE=-23
    int32 SENSOR_INFO_STALE=-24
    int32 COMMUNICATION_FAILURE=-25
    int32 CRASH=-29
    int32 ABORT=-30
    int32 NO_IK_SOLUTION=-31
    """,
)
RobotTrajectory = message(
    "moveit_msgs/RobotTrajectory",
    # The multi-DOF part (trajectory_msgs/MultiDOFJointTrajectory in ROS) is unused: an empty
    # joint trajectory stands in for it.
    "trajectory_msgs/JointTrajectory joint_trajectory\n"
    "trajectory_msgs/JointTrajectory multi_dof_joint_trajectory",
    "A planned motion: its joint trajectory (multi-DOF part unused).",
)
RobotState = message("moveit_msgs/RobotState", "sensor_msgs/JointState joint_state\nbool is_diff")
SolidPrimitive = message(
    "shape_msgs/SolidPrimitive",
    """
    uint8 type
    float64[] dimensions
    uint8 BOX=1
    uint8 SPHERE=2
    uint8 CYLINDER=3
    uint8 CONE=4
    uint8 BOX_X=0
    uint8 BOX_Y=1
    uint8 BOX_Z=2
    uint8 SPHERE_RADIUS=0
    """,
)
CollisionObject = message(
    "moveit_msgs/CollisionObject",
    """
    Header header
    string id
    shape_msgs/SolidPrimitive[] primitives
    geometry_msgs/Pose[] primitive_poses
    byte operation
    byte ADD=0
    byte REMOVE=1
    byte APPEND=2
    byte MOVE=3
    """,
    "A box of the planning scene (``primitives[0]``, at ``primitive_poses[0]`` in ``header.frame_id``: "
    "``world``, or the gripper's cup body when attached).",
)
AttachedCollisionObject = message(
    "moveit_msgs/AttachedCollisionObject",
    "string link_name\nCollisionObject object\nstring[] touch_links\nfloat64 weight",
)
DisplayTrajectory = message(
    "moveit_msgs/DisplayTrajectory",
    "string model_id\nRobotTrajectory[] trajectory\nRobotState trajectory_start",
)
ExecuteTrajectoryAction, ExecuteTrajectoryGoal, ExecuteTrajectoryResult, ExecuteTrajectoryFeedback = action(
    "moveit_msgs/ExecuteTrajectory",
    "RobotTrajectory trajectory\n---\nMoveItErrorCodes error_code\n---\nstring state",
    "The action type: ``SimpleActionClient('execute_trajectory', ExecuteTrajectoryAction)``.",
)
