"""flexbe_core.proxy.proxy_action_client of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.proxies import ProxyActionClient

__all__ = ["ProxyActionClient"]
