"""flexbe_core.proxy.proxy_transform_listener of omtp-drake flexbe-run."""

from omtp_drake.ros.flexbe.proxies import ProxyTransformListener

__all__ = ["ProxyTransformListener"]
