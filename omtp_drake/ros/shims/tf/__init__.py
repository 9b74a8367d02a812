"""tf (ROS 1's old tf) of omtp-drake ros-run: its transformations helpers and
TransformListener (on the cell's frames)."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import listener, transformations
from .listener import TransformListener

__all__ = ["TransformListener", "listener", "transformations"]
__getattr__ = module_getattr(__name__, __all__)
