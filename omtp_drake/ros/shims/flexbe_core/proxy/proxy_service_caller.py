"""flexbe_core.proxy.proxy_service_caller of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.proxies import ProxyServiceCaller

__all__ = ["ProxyServiceCaller"]
