"""moveit_commander.conversions of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.tf.convert import list_to_pose, pose_to_list

__all__ = ["list_to_pose", "pose_to_list"]
__getattr__ = module_getattr(__name__, __all__)
