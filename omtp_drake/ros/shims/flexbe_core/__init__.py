"""flexbe_core of omtp-drake flexbe-run: FlexBE's engine, headless, in simulated time."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.flexbe.behavior import Behavior
from omtp_drake.ros.flexbe.containers import ConcurrencyContainer, PriorityContainer
from omtp_drake.ros.flexbe.engine import Autonomy, EventState, Logger, OperatableStateMachine

from . import core, proxy

__all__ = [
    "Autonomy",
    "Behavior",
    "ConcurrencyContainer",
    "EventState",
    "Logger",
    "OperatableStateMachine",
    "PriorityContainer",
    "core",
    "proxy",
]
__getattr__ = module_getattr(__name__, __all__)
