"""gazebo_msgs.srv of omtp-drake ros-run."""

from omtp_drake.ros.gazebo_interfaces import (
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
from omtp_drake.ros.unsupported import module_getattr

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
