"""flexbe_states.publisher_bool_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import PublisherBoolState

__all__ = ["PublisherBoolState"]
