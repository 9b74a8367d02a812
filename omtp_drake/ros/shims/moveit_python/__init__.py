"""moveit_python of omtp-drake ros-run: MoveGroupInterface and PlanningSceneInterface."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.moveit_python import MoveGroupInterface, PlanningSceneInterface

__all__ = ["MoveGroupInterface", "PlanningSceneInterface"]
__getattr__ = module_getattr(__name__, __all__)
