"""moveit_commander.conversions of omtp-drake ros-run."""

from omtp_drake.ros.convert import list_to_pose, pose_to_list
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["list_to_pose", "pose_to_list"]
__getattr__ = module_getattr(__name__, __all__)
