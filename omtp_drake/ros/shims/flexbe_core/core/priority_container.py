"""flexbe_core.core.priority_container of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.containers import PriorityContainer

__all__ = ["PriorityContainer"]
