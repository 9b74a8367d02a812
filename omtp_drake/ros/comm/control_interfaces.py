"""control_msgs: the joint trajectory controller's state and ``follow_joint_trajectory`` action types.

Served by the ros_control controllers of a robot of your own
(:mod:`omtp_drake.ros.gazebo.ros_control_topics`): ``/<ns>/<controller>/state`` and
``actionlib.SimpleActionClient('/<ns>/<controller>/follow_joint_trajectory',
FollowJointTrajectoryAction)``.
"""

from __future__ import annotations

from omtp_drake.ros.comm.messages import JointTrajectory, JointTrajectoryPoint, action, message

JointTolerance = message(
    "control_msgs/JointTolerance", "string name\nfloat64 position\nfloat64 velocity\nfloat64 acceleration"
)
_STATE = (
    "Header header\nstring[] joint_names\ntrajectory_msgs/JointTrajectoryPoint desired\n"
    "trajectory_msgs/JointTrajectoryPoint actual\ntrajectory_msgs/JointTrajectoryPoint error"
)
JointTrajectoryControllerState = message("control_msgs/JointTrajectoryControllerState", _STATE)
(
    FollowJointTrajectoryAction,
    FollowJointTrajectoryGoal,
    FollowJointTrajectoryResult,
    FollowJointTrajectoryFeedback,
) = action(
    "control_msgs/FollowJointTrajectory",
    "trajectory_msgs/JointTrajectory trajectory\nJointTolerance[] path_tolerance\n"
    "JointTolerance[] goal_tolerance\nduration goal_time_tolerance\n---\n"
    "int32 error_code\nstring error_string\nint32 SUCCESSFUL=0\nint32 INVALID_GOAL=-1\n"
    "int32 INVALID_JOINTS=-2\nint32 OLD_HEADER_TIMESTAMP=-3\nint32 PATH_TOLERANCE_VIOLATED=-4\n"
    "int32 GOAL_TOLERANCE_VIOLATED=-5\n---\n" + _STATE,
    "The action type: ``SimpleActionClient('/arm_controller/follow_joint_trajectory', "
    "FollowJointTrajectoryAction)``.",
)

__all__ = [
    "FollowJointTrajectoryAction",
    "FollowJointTrajectoryFeedback",
    "FollowJointTrajectoryGoal",
    "FollowJointTrajectoryResult",
    "JointTolerance",
    "JointTrajectory",
    "JointTrajectoryControllerState",
    "JointTrajectoryPoint",
]
