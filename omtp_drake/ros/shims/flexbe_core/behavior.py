"""flexbe_core.behavior of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.behavior import Behavior

__all__ = ["Behavior"]
