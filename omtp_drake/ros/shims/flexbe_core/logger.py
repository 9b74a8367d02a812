"""flexbe_core.logger of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.engine import Logger

__all__ = ["Logger"]
