"""moveit_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.interfaces import (
    AttachedCollisionObject,
    CollisionObject,
    DisplayTrajectory,
    ExecuteTrajectoryAction,
    ExecuteTrajectoryFeedback,
    ExecuteTrajectoryGoal,
    ExecuteTrajectoryResult,
    MoveItErrorCodes,
    RobotState,
    RobotTrajectory,
)
from omtp_drake.ros.moveit_interfaces import (
    BoundingVolume,
    Constraints,
    JointConstraint,
    MotionPlanRequest,
    MoveGroupAction,
    MoveGroupFeedback,
    MoveGroupGoal,
    MoveGroupResult,
    OrientationConstraint,
    PlanningOptions,
    PlanningScene,
    PositionConstraint,
    PositionIKRequest,
    WorkspaceParameters,
)
from omtp_drake.ros.unsupported import module_getattr

__all__ = [
    "AttachedCollisionObject",
    "BoundingVolume",
    "CollisionObject",
    "Constraints",
    "DisplayTrajectory",
    "ExecuteTrajectoryAction",
    "ExecuteTrajectoryFeedback",
    "ExecuteTrajectoryGoal",
    "ExecuteTrajectoryResult",
    "JointConstraint",
    "MotionPlanRequest",
    "MoveGroupAction",
    "MoveGroupFeedback",
    "MoveGroupGoal",
    "MoveGroupResult",
    "MoveItErrorCodes",
    "OrientationConstraint",
    "PlanningOptions",
    "PlanningScene",
    "PositionConstraint",
    "PositionIKRequest",
    "RobotState",
    "RobotTrajectory",
    "WorkspaceParameters",
]
__getattr__ = module_getattr(__name__, __all__)
