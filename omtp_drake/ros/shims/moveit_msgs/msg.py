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
from omtp_drake.ros.unsupported import module_getattr

__all__ = [
    "AttachedCollisionObject",
    "CollisionObject",
    "DisplayTrajectory",
    "ExecuteTrajectoryAction",
    "ExecuteTrajectoryFeedback",
    "ExecuteTrajectoryGoal",
    "ExecuteTrajectoryResult",
    "MoveItErrorCodes",
    "RobotState",
    "RobotTrajectory",
]
__getattr__ = module_getattr(__name__, __all__)
