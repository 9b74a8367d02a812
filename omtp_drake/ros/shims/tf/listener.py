"""tf.listener of omtp-drake ros-run: ROS 1 tf's TransformListener on the cell's frames."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.tf.listener import TransformListener

__all__ = ["TransformListener"]
__getattr__ = module_getattr(__name__, __all__)
