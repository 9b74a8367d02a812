"""gazebo_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.gazebo.interfaces import LinkState, LinkStates, ModelState, ModelStates

__all__ = ["LinkState", "LinkStates", "ModelState", "ModelStates"]
__getattr__ = module_getattr(__name__, __all__)
