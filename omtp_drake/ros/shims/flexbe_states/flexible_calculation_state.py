"""flexbe_states.flexible_calculation_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import FlexibleCalculationState

__all__ = ["FlexibleCalculationState"]
