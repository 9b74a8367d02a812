"""actionlib_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.actions import GoalStatus
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["GoalStatus"]
__getattr__ = module_getattr(__name__, __all__)
