"""omtp_gazebo.srv of omtp-drake ros-run."""

from omtp_drake.ros.comm.interfaces import (
    ConveyorBeltControl,
    ConveyorBeltControlRequest,
    ConveyorBeltControlResponse,
    VacuumGripperControl,
    VacuumGripperControlRequest,
    VacuumGripperControlResponse,
)
from omtp_drake.ros.comm.unsupported import module_getattr

__all__ = [
    "ConveyorBeltControl",
    "ConveyorBeltControlRequest",
    "ConveyorBeltControlResponse",
    "VacuumGripperControl",
    "VacuumGripperControlRequest",
    "VacuumGripperControlResponse",
]
__getattr__ = module_getattr(__name__, __all__)
