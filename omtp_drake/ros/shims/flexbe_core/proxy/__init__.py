"""flexbe_core.proxy of omtp-drake flexbe-run: the proxies on the cell's topics, services and actions."""

from omtp_drake.ros.comm.unsupported import module_getattr
from omtp_drake.ros.flexbe.proxies import (
    ProxyActionClient,
    ProxyPublisher,
    ProxyServiceCaller,
    ProxySubscriberCached,
    ProxyTransformListener,
)

__all__ = [
    "ProxyActionClient",
    "ProxyPublisher",
    "ProxyServiceCaller",
    "ProxySubscriberCached",
    "ProxyTransformListener",
]
__getattr__ = module_getattr(__name__, __all__)
