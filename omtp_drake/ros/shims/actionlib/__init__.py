"""actionlib of omtp-drake ros-run: clients of MoveIt's execute_trajectory and move_group actions."""

from typing import Any

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.gazebo.ros_control_action import FollowJointTrajectoryClient, is_follow_joint_trajectory
from omtp_drake.ros.moveit import actions
from omtp_drake.ros.moveit.actions import GoalStatus
from omtp_drake.ros.moveit.move_group import MoveGroupClient, is_move_group


def SimpleActionClient(ns: str, ActionSpec: Any) -> Any:  # noqa: N802, N803 (actionlib's names)
    """The client of the cell's action server ``ns`` (``move_group``, ``execute_trajectory``, a
    ros_control trajectory controller's ``follow_joint_trajectory``)."""
    if is_move_group(ns, ActionSpec):
        return MoveGroupClient(ns)
    if is_follow_joint_trajectory(ActionSpec):
        return FollowJointTrajectoryClient(ns)
    return actions.SimpleActionClient(ns, ActionSpec)


class SimpleGoalState:
    PENDING, ACTIVE, DONE = 0, 1, 2


__all__ = ["GoalStatus", "SimpleActionClient", "SimpleGoalState"]
__getattr__ = module_getattr(__name__, __all__)
