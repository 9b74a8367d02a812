"""flexbe_states.operator_decision_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import OperatorDecisionState

__all__ = ["OperatorDecisionState"]
