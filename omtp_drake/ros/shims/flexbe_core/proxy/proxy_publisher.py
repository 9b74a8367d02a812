"""flexbe_core.proxy.proxy_publisher of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.proxies import ProxyPublisher

__all__ = ["ProxyPublisher"]
