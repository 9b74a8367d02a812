"""trajectory_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.messages import JointTrajectory, JointTrajectoryPoint
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["JointTrajectory", "JointTrajectoryPoint"]
__getattr__ = module_getattr(__name__, __all__)
