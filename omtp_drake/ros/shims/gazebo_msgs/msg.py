"""gazebo_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.gazebo_interfaces import LinkState, LinkStates, ModelState, ModelStates
from omtp_drake.ros.unsupported import module_getattr

__all__ = ["LinkState", "LinkStates", "ModelState", "ModelStates"]
__getattr__ = module_getattr(__name__, __all__)
