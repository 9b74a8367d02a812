"""std_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.messages import (
    Bool,
    Empty,
    Float64,
    Float64MultiArray,
    Header,
    Int32,
    MultiArrayDimension,
    MultiArrayLayout,
    String,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = [
    "Bool",
    "Empty",
    "Float64",
    "Float64MultiArray",
    "Header",
    "Int32",
    "MultiArrayDimension",
    "MultiArrayLayout",
    "String",
]
__getattr__ = module_getattr(__name__, __all__)
