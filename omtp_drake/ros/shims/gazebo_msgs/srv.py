"""gazebo_msgs.srv of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.gazebo.interfaces import (
    DeleteModel,
    DeleteModelRequest,
    DeleteModelResponse,
    GetLinkState,
    GetLinkStateRequest,
    GetLinkStateResponse,
    GetModelState,
    GetModelStateRequest,
    GetModelStateResponse,
    SetModelState,
    SetModelStateRequest,
    SetModelStateResponse,
    SpawnModel,
    SpawnModelRequest,
    SpawnModelResponse,
)

__all__ = [
    "DeleteModel",
    "DeleteModelRequest",
    "DeleteModelResponse",
    "GetLinkState",
    "GetLinkStateRequest",
    "GetLinkStateResponse",
    "GetModelState",
    "GetModelStateRequest",
    "GetModelStateResponse",
    "SetModelState",
    "SetModelStateRequest",
    "SetModelStateResponse",
    "SpawnModel",
    "SpawnModelRequest",
    "SpawnModelResponse",
]
__getattr__ = module_getattr(__name__, __all__)
