"""tf2_geometry_msgs of omtp-drake ros-run."""

from omtp_drake.ros.tf import do_transform_pose
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["do_transform_pose"]
__getattr__ = module_getattr(__name__, __all__)
