"""sensor_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.messages import JointState
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["JointState"]
__getattr__ = module_getattr(__name__, __all__)
