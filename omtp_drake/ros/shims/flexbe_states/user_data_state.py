"""flexbe_states.user_data_state of omtp-drake flexbe-run."""

from omtp_drake.flexbe.states import UserDataState

__all__ = ["UserDataState"]
