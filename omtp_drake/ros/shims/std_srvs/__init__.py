"""std_srvs of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr

from . import srv

__all__ = ["srv"]
__getattr__ = module_getattr(__name__, __all__)
