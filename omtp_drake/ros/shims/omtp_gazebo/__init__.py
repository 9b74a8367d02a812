"""omtp_gazebo of omtp-drake ros-run: the course cell's messages and services."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import msg, srv

__all__ = ["msg", "srv"]
__getattr__ = module_getattr(__name__, __all__)
