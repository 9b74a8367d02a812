"""flexbe_states.wait_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import WaitState

__all__ = ["WaitState"]
