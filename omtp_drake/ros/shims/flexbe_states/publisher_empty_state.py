"""flexbe_states.publisher_empty_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import PublisherEmptyState

__all__ = ["PublisherEmptyState"]
