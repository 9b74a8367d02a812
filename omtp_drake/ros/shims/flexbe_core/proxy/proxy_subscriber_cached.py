"""flexbe_core.proxy.proxy_subscriber_cached of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.proxies import ProxySubscriberCached

__all__ = ["ProxySubscriberCached"]
