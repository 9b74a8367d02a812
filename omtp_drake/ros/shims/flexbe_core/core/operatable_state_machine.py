"""flexbe_core.core.operatable_state_machine of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.engine import OperatableStateMachine

__all__ = ["OperatableStateMachine"]
