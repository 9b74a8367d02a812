"""moveit_commander.exception of omtp-drake ros-run."""

from omtp_drake.ros.moveit import MoveItCommanderException
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["MoveItCommanderException"]
__getattr__ = module_getattr(__name__, __all__)
