"""moveit_msgs.srv of omtp-drake ros-run: ``/compute_ik``'s GetPositionIK."""

from omtp_drake.ros.moveit_interfaces import GetPositionIK, GetPositionIKRequest, GetPositionIKResponse
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["GetPositionIK", "GetPositionIKRequest", "GetPositionIKResponse"]
__getattr__ = module_getattr(__name__, __all__)
