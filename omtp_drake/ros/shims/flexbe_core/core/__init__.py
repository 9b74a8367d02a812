"""flexbe_core.core of omtp-drake flexbe-run."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.flexbe.containers import ConcurrencyContainer, PriorityContainer
from omtp_drake.ros.flexbe.engine import EventState, OperatableStateMachine, State
from omtp_drake.ros.flexbe.userdata import StateError, StateMachineError, UserData, UserDataError

__all__ = [
    "ConcurrencyContainer",
    "EventState",
    "OperatableStateMachine",
    "PriorityContainer",
    "State",
    "StateError",
    "StateMachineError",
    "UserData",
    "UserDataError",
]
__getattr__ = module_getattr(__name__, __all__)
