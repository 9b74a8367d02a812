"""tf2_ros of omtp-drake ros-run: the cell's tf buffer."""

from omtp_drake.ros.tf import (
    Buffer,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
    TransformListener,
)
from omtp_drake.ros.unsupported import module_getattr

__all__ = [
    "Buffer",
    "ConnectivityException",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "TimeoutException",
    "TransformException",
    "TransformListener",
]
__getattr__ = module_getattr(__name__, __all__)
