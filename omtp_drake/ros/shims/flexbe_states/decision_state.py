"""flexbe_states.decision_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import DecisionState

__all__ = ["DecisionState"]
