"""flexbe_core.core.exceptions of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.userdata import StateError, StateMachineError, UserDataError

__all__ = ["StateError", "StateMachineError", "UserDataError"]
