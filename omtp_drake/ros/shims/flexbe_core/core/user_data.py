"""flexbe_core.core.user_data of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.userdata import UserData

__all__ = ["UserData"]
