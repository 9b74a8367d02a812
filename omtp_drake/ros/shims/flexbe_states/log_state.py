"""flexbe_states.log_state of omtp-drake flexbe-run."""

from omtp_drake.flexbe.states import LogState

__all__ = ["LogState"]
