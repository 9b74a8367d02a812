"""flexbe_states.calculation_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import CalculationState

__all__ = ["CalculationState"]
