"""moveit_msgs.srv of omtp-drake ros-run: move_group's kinematics services
(``/compute_ik``, ``/compute_fk``, ``/compute_cartesian_path``)."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.interfaces import (
    GetCartesianPath,
    GetCartesianPathRequest,
    GetCartesianPathResponse,
    GetPositionFK,
    GetPositionFKRequest,
    GetPositionFKResponse,
    GetPositionIK,
    GetPositionIKRequest,
    GetPositionIKResponse,
)

__all__ = [
    "GetCartesianPath",
    "GetCartesianPathRequest",
    "GetCartesianPathResponse",
    "GetPositionFK",
    "GetPositionFKRequest",
    "GetPositionFKResponse",
    "GetPositionIK",
    "GetPositionIKRequest",
    "GetPositionIKResponse",
]
__getattr__ = module_getattr(__name__, __all__)
