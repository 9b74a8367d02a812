"""flexbe_states.input_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import InputState

__all__ = ["InputState"]
