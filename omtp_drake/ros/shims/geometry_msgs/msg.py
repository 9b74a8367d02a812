"""geometry_msgs.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.messages import (
    Header,
    Point,
    Pose,
    Pose2D,
    PoseArray,
    PoseStamped,
    Quaternion,
    Transform,
    TransformStamped,
    Twist,
    Vector3,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = [
    "Header",
    "Point",
    "Pose",
    "Pose2D",
    "PoseArray",
    "PoseStamped",
    "Quaternion",
    "Transform",
    "TransformStamped",
    "Twist",
    "Vector3",
]
__getattr__ = module_getattr(__name__, __all__)
