"""flexbe_core.core.event_state of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.engine import EventState

__all__ = ["EventState"]
