"""flexbe_states.log_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import LogState

__all__ = ["LogState"]
