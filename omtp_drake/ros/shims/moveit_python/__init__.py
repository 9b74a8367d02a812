"""moveit_python of omtp-drake ros-run: MoveGroupInterface and PlanningSceneInterface."""

from omtp_drake.ros.moveit_python import MoveGroupInterface, PlanningSceneInterface
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["MoveGroupInterface", "PlanningSceneInterface"]
__getattr__ = module_getattr(__name__, __all__)
