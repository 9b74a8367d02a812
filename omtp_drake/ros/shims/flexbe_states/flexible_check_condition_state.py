"""flexbe_states.flexible_check_condition_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import FlexibleCheckConditionState

__all__ = ["FlexibleCheckConditionState"]
