"""moveit_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.interfaces import (
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
from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.interfaces import (
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
