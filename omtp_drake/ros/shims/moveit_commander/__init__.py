"""moveit_commander of omtp-drake ros-run."""

from omtp_drake.ros.moveit import MoveGroupCommander, MoveItCommanderException
from omtp_drake.ros.planning_scene import PlanningSceneInterface
from omtp_drake.ros.robot import RobotCommander, roscpp_initialize, roscpp_shutdown
from omtp_drake.ros.unsupported import module_getattr

from . import conversions

__all__ = [
    "MoveGroupCommander",
    "MoveItCommanderException",
    "PlanningSceneInterface",
    "RobotCommander",
    "conversions",
    "roscpp_initialize",
    "roscpp_shutdown",
]
__getattr__ = module_getattr(__name__, __all__)
