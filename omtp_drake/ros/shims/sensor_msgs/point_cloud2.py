"""sensor_msgs.point_cloud2 of omtp-drake ros-run."""

from omtp_drake.ros.comm.image_messages import read_points
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["read_points"]
__getattr__ = module_getattr(__name__, __all__)
