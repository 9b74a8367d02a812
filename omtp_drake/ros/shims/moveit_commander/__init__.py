"""moveit_commander of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.commander import MoveGroupCommander, MoveItCommanderException
from omtp_drake.ros.moveit.planning_scene import PlanningSceneInterface
from omtp_drake.ros.moveit.robot import RobotCommander, roscpp_initialize, roscpp_shutdown

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
