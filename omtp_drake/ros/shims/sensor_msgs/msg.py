"""sensor_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.image_messages import CameraInfo, Image, PointCloud2, PointField, RegionOfInterest
from omtp_drake.ros.comm.messages import JointState
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["CameraInfo", "Image", "JointState", "PointCloud2", "PointField", "RegionOfInterest"]
__getattr__ = module_getattr(__name__, __all__)
