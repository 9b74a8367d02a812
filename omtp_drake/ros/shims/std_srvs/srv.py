"""std_srvs.srv of omtp-drake ros-run."""

from omtp_drake.ros.comm.interfaces import (
    EmptyRequest,
    EmptyResponse,
    SetBool,
    SetBoolRequest,
    SetBoolResponse,
    Trigger,
    TriggerRequest,
    TriggerResponse,
)
from omtp_drake.ros.comm.interfaces import EmptyService as Empty
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = [
    "Empty",
    "EmptyRequest",
    "EmptyResponse",
    "SetBool",
    "SetBoolRequest",
    "SetBoolResponse",
    "Trigger",
    "TriggerRequest",
    "TriggerResponse",
]
__getattr__ = module_getattr(__name__, __all__)
