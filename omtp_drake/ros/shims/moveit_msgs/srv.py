"""moveit_msgs.srv of omtp-drake ros-run: ``/compute_ik``'s GetPositionIK."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.moveit.interfaces import GetPositionIK, GetPositionIKRequest, GetPositionIKResponse

__all__ = ["GetPositionIK", "GetPositionIKRequest", "GetPositionIKResponse"]
__getattr__ = module_getattr(__name__, __all__)
