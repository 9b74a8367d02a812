"""actionlib of omtp-drake ros-run: the client of MoveIt's execute_trajectory action."""

from omtp_drake.ros.commander import GoalStatus, SimpleActionClient
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["GoalStatus", "SimpleActionClient"]
__getattr__ = module_getattr(__name__, __all__)
