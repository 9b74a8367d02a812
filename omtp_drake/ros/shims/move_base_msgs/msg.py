"""move_base_msgs.msg of omtp-drake ros-run: the move_base action's types (no server)."""

from omtp_drake.ros.comm.nav_interfaces import MoveBaseAction, MoveBaseFeedback, MoveBaseGoal, MoveBaseResult
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["MoveBaseAction", "MoveBaseFeedback", "MoveBaseGoal", "MoveBaseResult"]
__getattr__ = module_getattr(__name__, __all__)
