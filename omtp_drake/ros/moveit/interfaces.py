"""moveit_msgs types of MoveIt's ``/move_group`` action and its kinematics services
(``/compute_ik``, ``/compute_fk``, ``/compute_cartesian_path``).

Field names and order follow ``moveit_msgs`` (Noetic): ``MoveGroupGoal`` =
``MotionPlanRequest request`` + ``PlanningOptions planning_options``;
``Constraints`` hold joint, position and orientation constraints;
``GetPositionIK`` takes a ``PositionIKRequest``; ``GetPositionFK`` and
``GetCartesianPath`` are Noetic's (the Cartesian request's jump thresholds and
Cartesian speed included). Fields this cell does not use
(workspace bounds, visibility constraints, planning-scene diffs) are kept so
scripts that set them still run; what they would change is not modelled.
"""

from __future__ import annotations

from typing import ClassVar

from omtp_drake.ros.comm.interfaces import (
    MoveItErrorCodes,
    RobotState,
    RobotTrajectory,
    ServiceType,
    SolidPrimitive,
)
from omtp_drake.ros.comm.messages import Duration, Header, Message, Pose, PoseStamped, Quaternion, Vector3


class JointConstraint(Message):
    __slots__ = ("joint_name", "position", "tolerance_above", "tolerance_below", "weight")
    _type = "moveit_msgs/JointConstraint"
    _defaults = (str, float, float, float, float)


class BoundingVolume(Message):
    __slots__ = ("primitives", "primitive_poses", "meshes", "mesh_poses")
    _type = "moveit_msgs/BoundingVolume"
    _defaults = (list, list, list, list)


class PositionConstraint(Message):
    __slots__ = ("header", "link_name", "target_point_offset", "constraint_region", "weight")
    _type = "moveit_msgs/PositionConstraint"
    _defaults = (Header, str, Vector3, BoundingVolume, float)


class OrientationConstraint(Message):
    __slots__ = (
        "header",
        "orientation",
        "link_name",
        "absolute_x_axis_tolerance",
        "absolute_y_axis_tolerance",
        "absolute_z_axis_tolerance",
        "parameterization",
        "weight",
    )
    _type = "moveit_msgs/OrientationConstraint"
    _defaults = (Header, Quaternion, str, float, float, float, int, float)
    XYZ_EULER_ANGLES: ClassVar[int] = 0
    ROTATION_VECTOR: ClassVar[int] = 1


class Constraints(Message):
    __slots__ = (
        "name",
        "joint_constraints",
        "position_constraints",
        "orientation_constraints",
        "visibility_constraints",
    )
    _type = "moveit_msgs/Constraints"
    _defaults = (str, list, list, list, list)


class WorkspaceParameters(Message):
    __slots__ = ("header", "min_corner", "max_corner")
    _type = "moveit_msgs/WorkspaceParameters"
    _defaults = (Header, Vector3, Vector3)


class MotionPlanRequest(Message):
    __slots__ = (
        "workspace_parameters",
        "start_state",
        "goal_constraints",
        "path_constraints",
        "trajectory_constraints",
        "reference_trajectories",
        "pipeline_id",
        "planner_id",
        "group_name",
        "num_planning_attempts",
        "allowed_planning_time",
        "max_velocity_scaling_factor",
        "max_acceleration_scaling_factor",
        "cartesian_speed_end_effector_link",
        "max_cartesian_speed",
    )
    _type = "moveit_msgs/MotionPlanRequest"
    _defaults = (
        WorkspaceParameters,
        RobotState,
        list,
        Constraints,
        list,
        list,
        str,
        str,
        str,
        int,
        float,
        float,
        float,
        str,
        float,
    )


class PlanningScene(Message):
    """A planning-scene diff (kept as given; the cell's scene is ``PlanningSceneInterface``'s)."""

    __slots__ = ("name", "robot_state", "is_diff")
    _type = "moveit_msgs/PlanningScene"
    _defaults = (str, RobotState, bool)


class PlanningOptions(Message):
    __slots__ = (
        "planning_scene_diff",
        "plan_only",
        "look_around",
        "look_around_attempts",
        "max_safe_execution_cost",
        "replan",
        "replan_attempts",
        "replan_delay",
    )
    _type = "moveit_msgs/PlanningOptions"
    _defaults = (PlanningScene, bool, bool, int, float, bool, int, float)


class MoveGroupGoal(Message):
    __slots__ = ("request", "planning_options")
    _type = "moveit_msgs/MoveGroupGoal"
    _defaults = (MotionPlanRequest, PlanningOptions)


class MoveGroupResult(Message):
    __slots__ = (
        "error_code",
        "trajectory_start",
        "planned_trajectory",
        "executed_trajectory",
        "planning_time",
    )
    _type = "moveit_msgs/MoveGroupResult"
    _defaults = (MoveItErrorCodes, RobotState, RobotTrajectory, RobotTrajectory, float)


class MoveGroupFeedback(Message):
    __slots__ = ("state",)
    _type = "moveit_msgs/MoveGroupFeedback"
    _defaults = (str,)


class MoveGroupAction(Message):
    """The action type: ``SimpleActionClient('move_group', MoveGroupAction)``."""

    __slots__ = ()
    _type = "moveit_msgs/MoveGroupAction"
    _goal_class: ClassVar[type[Message]] = MoveGroupGoal
    _result_class: ClassVar[type[Message]] = MoveGroupResult
    _feedback_class: ClassVar[type[Message]] = MoveGroupFeedback


class PositionIKRequest(Message):
    __slots__ = (
        "group_name",
        "robot_state",
        "constraints",
        "avoid_collisions",
        "ik_link_name",
        "pose_stamped",
        "ik_link_names",
        "pose_stamped_vector",
        "timeout",
        "attempts",
    )
    _type = "moveit_msgs/PositionIKRequest"
    _defaults = (str, RobotState, Constraints, bool, str, PoseStamped, list, list, Duration, int)


class GetPositionIKRequest(Message):
    __slots__ = ("ik_request",)
    _type = "moveit_msgs/GetPositionIKRequest"
    _defaults = (PositionIKRequest,)


class GetPositionIKResponse(Message):
    __slots__ = ("solution", "error_code")
    _type = "moveit_msgs/GetPositionIKResponse"
    _defaults = (RobotState, MoveItErrorCodes)


class GetPositionIK(ServiceType):
    _type = "moveit_msgs/GetPositionIK"
    _request_class = GetPositionIKRequest
    _response_class = GetPositionIKResponse


class GetPositionFKRequest(Message):
    __slots__ = ("header", "fk_link_names", "robot_state")
    _type = "moveit_msgs/GetPositionFKRequest"
    _defaults = (Header, list, RobotState)


class GetPositionFKResponse(Message):
    __slots__ = ("pose_stamped", "fk_link_names", "error_code")
    _type = "moveit_msgs/GetPositionFKResponse"
    _defaults = (list, list, MoveItErrorCodes)


class GetPositionFK(ServiceType):
    _type = "moveit_msgs/GetPositionFK"
    _request_class = GetPositionFKRequest
    _response_class = GetPositionFKResponse


class GetCartesianPathRequest(Message):
    __slots__ = (
        "header",
        "start_state",
        "group_name",
        "link_name",
        "waypoints",
        "max_step",
        "jump_threshold",
        "prismatic_jump_threshold",
        "revolute_jump_threshold",
        "avoid_collisions",
        "path_constraints",
        "cartesian_speed_limited_link",
        "max_cartesian_speed",
    )
    _type = "moveit_msgs/GetCartesianPathRequest"
    _defaults = (
        Header,
        RobotState,
        str,
        str,
        list,
        float,
        float,
        float,
        float,
        bool,
        Constraints,
        str,
        float,
    )


class GetCartesianPathResponse(Message):
    __slots__ = ("start_state", "solution", "fraction", "error_code")
    _type = "moveit_msgs/GetCartesianPathResponse"
    _defaults = (RobotState, RobotTrajectory, float, MoveItErrorCodes)


class GetCartesianPath(ServiceType):
    _type = "moveit_msgs/GetCartesianPath"
    _request_class = GetCartesianPathRequest
    _response_class = GetCartesianPathResponse


__all__ = [
    "BoundingVolume",
    "Constraints",
    "GetCartesianPath",
    "GetCartesianPathRequest",
    "GetCartesianPathResponse",
    "GetPositionFK",
    "GetPositionFKRequest",
    "GetPositionFKResponse",
    "GetPositionIK",
    "GetPositionIKRequest",
    "GetPositionIKResponse",
    "JointConstraint",
    "MotionPlanRequest",
    "MoveGroupAction",
    "MoveGroupFeedback",
    "MoveGroupGoal",
    "MoveGroupResult",
    "OrientationConstraint",
    "PlanningOptions",
    "PlanningScene",
    "Pose",
    "PositionConstraint",
    "PositionIKRequest",
    "SolidPrimitive",
    "WorkspaceParameters",
]
