"""moveit_msgs of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import msg, srv

__all__ = ["msg", "srv"]
__getattr__ = module_getattr(__name__, __all__)
