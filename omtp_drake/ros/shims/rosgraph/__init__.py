"""rosgraph of omtp-drake ros-run: the master's graph calls on the run's session
(omtp_drake.ros.comm.master)."""

from omtp_drake.ros.comm.master import (
    Master,
    MasterError,
    MasterException,
    MasterFailure,
    get_master_uri,
    is_master_online,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["Master", "MasterError", "MasterException", "MasterFailure", "get_master_uri", "is_master_online"]
__getattr__ = module_getattr(__name__, __all__)
