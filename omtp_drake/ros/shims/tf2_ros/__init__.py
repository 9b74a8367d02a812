"""tf2_ros of omtp-drake ros-run: the cell's tf buffer."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.tf.tf2 import (
    Buffer,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
    TransformListener,
)

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
