"""flexbe_states.user_data_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import UserDataState

__all__ = ["UserDataState"]
