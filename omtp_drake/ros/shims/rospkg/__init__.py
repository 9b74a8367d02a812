"""rospkg of omtp-drake flexbe-run: the packages of the run's catkin workspaces."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.flexbe.workspace import ResourceNotFound, RosPack

__all__ = ["ResourceNotFound", "RosPack"]
__getattr__ = module_getattr(__name__, __all__)
