"""shape_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.interfaces import SolidPrimitive
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["SolidPrimitive"]
__getattr__ = module_getattr(__name__, __all__)
