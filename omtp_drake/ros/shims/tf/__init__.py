"""tf (ROS 1's old tf) of omtp-drake ros-run: only its transformations helpers."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import transformations

__all__ = ["transformations"]
__getattr__ = module_getattr(__name__, __all__)
