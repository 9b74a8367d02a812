"""control_msgs of omtp-drake ros-run (a robot's ros_control trajectory controllers)."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import msg

__all__ = ["msg"]
__getattr__ = module_getattr(__name__, __all__)
