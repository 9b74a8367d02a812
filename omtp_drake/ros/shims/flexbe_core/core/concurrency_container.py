"""flexbe_core.core.concurrency_container of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.containers import ConcurrencyContainer

__all__ = ["ConcurrencyContainer"]
