"""tf.transformations of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.tf.transformations import (
    euler_from_quaternion,
    euler_matrix,
    quaternion_conjugate,
    quaternion_from_euler,
    quaternion_from_matrix,
    quaternion_inverse,
    quaternion_matrix,
    quaternion_multiply,
    translation_from_matrix,
    translation_matrix,
)

__all__ = [
    "euler_from_quaternion",
    "euler_matrix",
    "quaternion_conjugate",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_inverse",
    "quaternion_matrix",
    "quaternion_multiply",
    "translation_from_matrix",
    "translation_matrix",
]
__getattr__ = module_getattr(__name__, __all__)
