"""rostopic of omtp-drake ros-run: a topic's type, from the cell's topics and the run's publishers."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.flexbe.topics import get_topic_class, get_topic_type

__all__ = ["get_topic_class", "get_topic_type"]
__getattr__ = module_getattr(__name__, __all__)
