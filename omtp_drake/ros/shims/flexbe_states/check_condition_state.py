"""flexbe_states.check_condition_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import CheckConditionState

__all__ = ["CheckConditionState"]
