"""actionlib_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.actions import GoalStatus

__all__ = ["GoalStatus"]
__getattr__ = module_getattr(__name__, __all__)
