"""control_msgs.msg of omtp-drake ros-run: the trajectory controller's state and action types."""

from omtp_drake.ros.comm.control_interfaces import (
    FollowJointTrajectoryAction,
    FollowJointTrajectoryFeedback,
    FollowJointTrajectoryGoal,
    FollowJointTrajectoryResult,
    JointTolerance,
    JointTrajectoryControllerState,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = [
    "FollowJointTrajectoryAction",
    "FollowJointTrajectoryFeedback",
    "FollowJointTrajectoryGoal",
    "FollowJointTrajectoryResult",
    "JointTolerance",
    "JointTrajectoryControllerState",
]
__getattr__ = module_getattr(__name__, __all__)
