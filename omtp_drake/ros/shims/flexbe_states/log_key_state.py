"""flexbe_states.log_key_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import LogKeyState

__all__ = ["LogKeyState"]
