"""tf2_geometry_msgs of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.tf.tf2 import do_transform_pose

__all__ = ["do_transform_pose"]
__getattr__ = module_getattr(__name__, __all__)
