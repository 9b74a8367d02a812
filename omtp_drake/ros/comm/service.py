"""rospy's services (``rospy.service``, ``rospy.impl.tcpros_service``): ServiceProxy,
``wait_for_service``; serving one from a script is not provided.

The cell's services are :mod:`omtp_drake.ros.gazebo.cell_services` (and Gazebo's, the
spawner's); a call takes the session's ``service`` latency before its handler runs.
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.ros.comm.client import resolve_name
from omtp_drake.ros.comm.exceptions import ROSException, ServiceException
from omtp_drake.ros.comm.rostime import _blocking
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.gazebo.cell_services import ServiceFailure


def _service(name: str) -> Any:
    session = current()
    key = resolve_name(name)
    if key not in session.services:
        raise ServiceException(
            f"service [{key}] unavailable: this cell has "
            + (", ".join(sorted(session.services)) or "no services")
        )
    return session.services[key]


def wait_for_service(service: str, timeout: Optional[float] = None) -> None:
    """Returns at once for a service of the cell; the cell's services are fixed, so
    for any other name it raises ROSException naming the ones there are."""
    try:
        _service(service)
    except ServiceException as e:
        raise ROSException(f"timeout exceeded while waiting for service: {e}") from None


class ServiceProxy:
    """rospy.ServiceProxy: call it with the request's fields or a request object."""

    def __init__(self, name: str, service_class: Any, persistent: bool = False, headers: Any = None):
        self.resolved_name = resolve_name(name)
        self.service_class = service_class

    def wait_for_service(self, timeout: Optional[float] = None) -> None:
        wait_for_service(self.resolved_name, timeout)

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.call(*args, **kwargs)

    def call(self, *args: Any, **kwargs: Any) -> Any:
        service = _service(self.resolved_name)
        if service.type is not self.service_class:
            raise ServiceException(
                f"service [{self.resolved_name}] has type {service.type._type}, not "
                f"{getattr(self.service_class, '_type', self.service_class)}"
            )
        request_class = service.type._request_class
        if len(args) == 1 and not kwargs and isinstance(args[0], request_class):
            request = args[0]
        else:
            try:
                request = request_class(*args, **kwargs)
            except TypeError as e:
                raise ServiceException(f"service [{self.resolved_name}]: {e}") from None
        with _blocking():
            session = current()
            session.think(session.latency.service)  # the call's way there
            try:
                return service.handler(request)
            except ServiceFailure as e:
                raise ServiceException(f"service [{self.resolved_name}] failed: {e}") from None

    def close(self) -> None:
        pass


def Service(name: str, service_class: Any, handler: Any, **_: Any) -> Any:  # noqa: N802 (rospy's name)
    not_supported(
        "rospy.Service (serving a service from a script)",
        "the cell's services are " + ", ".join(sorted(current().services)),
    )
