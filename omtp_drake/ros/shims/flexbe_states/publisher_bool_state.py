"""flexbe_states.publisher_bool_state of omtp-drake flexbe-run."""

from omtp_drake.flexbe.states import PublisherBoolState

__all__ = ["PublisherBoolState"]
