"""move_base_msgs of omtp-drake ros-run (the cell has no /move_base server)."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import msg

__all__ = ["msg"]
__getattr__ = module_getattr(__name__, __all__)
