"""flexbe_states.publisher_string_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import PublisherStringState

__all__ = ["PublisherStringState"]
