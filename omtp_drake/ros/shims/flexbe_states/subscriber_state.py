"""flexbe_states.subscriber_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.states import SubscriberState

__all__ = ["SubscriberState"]
