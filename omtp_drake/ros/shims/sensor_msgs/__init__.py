"""sensor_msgs of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import msg, point_cloud2

__all__ = ["msg", "point_cloud2"]
__getattr__ = module_getattr(__name__, __all__)
