"""moveit_msgs types of MoveIt's ``/move_group`` action and its kinematics services
(``/compute_ik``, ``/compute_fk``, ``/compute_cartesian_path``), declared from their
``.msg`` / ``.srv`` / ``.action`` text (:mod:`omtp_drake.ros.comm.messages`'s factory).

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

import omtp_drake.ros.comm.interfaces  # noqa: F401  (defines RobotState, MoveItErrorCodes... named here)
from omtp_drake.ros.comm.messages import action, message, service

JointConstraint = message(
    "moveit_msgs/JointConstraint",
    "string joint_name\nfloat64 position\nfloat64 tolerance_above\nfloat64 tolerance_below\nfloat64 weight",
)
BoundingVolume = message(
    "moveit_msgs/BoundingVolume",
    "shape_msgs/SolidPrimitive[] primitives\ngeometry_msgs/Pose[] primitive_poses\n"
    "shape_msgs/Mesh[] meshes\ngeometry_msgs/Pose[] mesh_poses",
)
PositionConstraint = message(
    "moveit_msgs/PositionConstraint",
    "Header header\nstring link_name\ngeometry_msgs/Vector3 target_point_offset\n"
    "BoundingVolume constraint_region\nfloat64 weight",
)
OrientationConstraint = message(
    "moveit_msgs/OrientationConstraint",
    """
    Header header
    geometry_msgs/Quaternion orientation
    string link_name
    float64 absolute_x_axis_tolerance
    float64 absolute_y_axis_tolerance
    float64 absolute_z_axis_tolerance
    uint8 parameterization
    float64 weight
    uint8 XYZ_EULER_ANGLES=0
    uint8 ROTATION_VECTOR=1
    """,
)
Constraints = message(
    "moveit_msgs/Constraints",
    "string name\nJointConstraint[] joint_constraints\nPositionConstraint[] position_constraints\n"
    "OrientationConstraint[] orientation_constraints\nVisibilityConstraint[] visibility_constraints",
)
WorkspaceParameters = message(
    "moveit_msgs/WorkspaceParameters",
    "Header header\ngeometry_msgs/Vector3 min_corner\ngeometry_msgs/Vector3 max_corner",
)
MotionPlanRequest = message(
    "moveit_msgs/MotionPlanRequest",
    """
    WorkspaceParameters workspace_parameters
    RobotState start_state
    Constraints[] goal_constraints
    Constraints path_constraints
    TrajectoryConstraints[] trajectory_constraints
    GenericTrajectory[] reference_trajectories
    string pipeline_id
    string planner_id
    string group_name
    int32 num_planning_attempts
    float64 allowed_planning_time
    float64 max_velocity_scaling_factor
    float64 max_acceleration_scaling_factor
    string cartesian_speed_end_effector_link
    float64 max_cartesian_speed
    """,
)
PlanningScene = message(
    "moveit_msgs/PlanningScene",
    # The fields a diff of this cell can carry; the rest of a planning scene is not modelled.
    "string name\nRobotState robot_state\nbool is_diff",
    "A planning-scene diff (kept as given; the cell's scene is ``PlanningSceneInterface``'s).",
)
PlanningOptions = message(
    "moveit_msgs/PlanningOptions",
    """
    PlanningScene planning_scene_diff
    bool plan_only
    bool look_around
    int32 look_around_attempts
    float64 max_safe_execution_cost
    bool replan
    int32 replan_attempts
    float64 replan_delay
    """,
)
MoveGroupAction, MoveGroupGoal, MoveGroupResult, MoveGroupFeedback = action(
    "moveit_msgs/MoveGroup",
    """
    MotionPlanRequest request
    PlanningOptions planning_options
    ---
    MoveItErrorCodes error_code
    RobotState trajectory_start
    RobotTrajectory planned_trajectory
    RobotTrajectory executed_trajectory
    float64 planning_time
    ---
    string state
    """,
    "The action type: ``SimpleActionClient('move_group', MoveGroupAction)``.",
)
PositionIKRequest = message(
    "moveit_msgs/PositionIKRequest",
    """
    string group_name
    RobotState robot_state
    Constraints constraints
    bool avoid_collisions
    string ik_link_name
    geometry_msgs/PoseStamped pose_stamped
    string[] ik_link_names
    geometry_msgs/PoseStamped[] pose_stamped_vector
    duration timeout
    int32 attempts
    """,
)
GetPositionIK, GetPositionIKRequest, GetPositionIKResponse = service(
    "moveit_msgs/GetPositionIK",
    "PositionIKRequest ik_request\n---\nRobotState solution\nMoveItErrorCodes error_code",
)
GetPositionFK, GetPositionFKRequest, GetPositionFKResponse = service(
    "moveit_msgs/GetPositionFK",
    """
    Header header
    string[] fk_link_names
    RobotState robot_state
    ---
    geometry_msgs/PoseStamped[] pose_stamped
    string[] fk_link_names
    MoveItErrorCodes error_code
    """,
)
GetCartesianPath, GetCartesianPathRequest, GetCartesianPathResponse = service(
    "moveit_msgs/GetCartesianPath",
    """
    Header header
    RobotState start_state
    string group_name
    string link_name
    geometry_msgs/Pose[] waypoints
    float64 max_step
    float64 jump_threshold
    float64 prismatic_jump_threshold
    float64 revolute_jump_threshold
    bool avoid_collisions
    Constraints path_constraints
    string cartesian_speed_limited_link
    float64 max_cartesian_speed
    ---
    RobotState start_state
    RobotTrajectory solution
    float64 fraction
    MoveItErrorCodes error_code
    """,
)
