"""moveit_commander.exception of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.commander import MoveItCommanderException

__all__ = ["MoveItCommanderException"]
__getattr__ = module_getattr(__name__, __all__)
