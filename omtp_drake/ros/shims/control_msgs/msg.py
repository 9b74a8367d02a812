"""control_msgs.msg of omtp-drake ros-run: the trajectory controller's state and action types
(those of :mod:`omtp_drake.ros.comm.control_interfaces` that control_msgs itself defines)."""

from omtp_drake.ros.comm import control_interfaces as _interfaces
from omtp_drake.ros.comm.unsupported import module_getattr

#: trajectory_msgs' types, which control_interfaces also exports, are trajectory_msgs.msg's here.
__all__ = [n for n in _interfaces.__all__ if not n.startswith("JointTrajectory") or n.endswith("State")]
globals().update({name: getattr(_interfaces, name) for name in __all__})
__getattr__ = module_getattr(__name__, __all__)
