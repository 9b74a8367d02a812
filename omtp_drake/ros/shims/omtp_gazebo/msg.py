"""omtp_gazebo.msg of omtp-drake ros-run."""

from omtp_drake.ros.comm.interfaces import (
    ConveyorBeltState,
    LogicalCameraImage,
    Model,
    Proximity,
    VacuumGripperState,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = ["ConveyorBeltState", "LogicalCameraImage", "Model", "Proximity", "VacuumGripperState"]
__getattr__ = module_getattr(__name__, __all__)
