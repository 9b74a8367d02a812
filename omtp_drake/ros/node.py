"""rospy: a node, simulated time, topics, services and logging on the current session.

The names and call shapes are rospy's; see :mod:`omtp_drake.ros.session` for
how time and callbacks run. Time is the cell's simulated time: ``sleep``,
``Rate.sleep``, ``spin`` and ``wait_for_message`` advance it. A blocking call
during or after shutdown (``signal_shutdown``, ``--timeout``) raises
:class:`ROSInterruptException`, as rospy's do.
"""

from __future__ import annotations

import contextlib
import copy
import logging
import math
import sys
from collections.abc import Callable, Iterator
from typing import Any, Optional

from omtp_drake.ros import messages, names, params
from omtp_drake.ros.messages import Duration, Message
from omtp_drake.ros.services import ServiceFailure
from omtp_drake.ros.session import ShutdownError, current, finite_seconds
from omtp_drake.ros.unsupported import not_supported

_log = logging.getLogger("rospy")


class Time(messages.Time):
    """rospy.Time: genpy's Time and ``now()``, the cell's simulated time."""

    __slots__ = ()

    @classmethod
    def now(cls) -> Time:
        return cls(0, int(round(current().time * 1e9)))


class ROSException(Exception):
    """rospy's base exception."""


class ROSInterruptException(ROSException, KeyboardInterrupt):
    """A blocking call was interrupted by shutdown."""


class ROSInitException(ROSException):
    pass


class ROSSerializationException(ROSException):
    pass


class ROSTimeMovedBackwardsException(ROSInterruptException):
    pass


class ServiceException(ROSException):
    """A service call failed (no such service, wrong type, or the service failed)."""


@contextlib.contextmanager
def _blocking() -> Iterator[None]:
    """A blocking call: shutdown becomes ROSInterruptException; callbacks due run after it."""
    session = current()
    try:
        session.check_running()
        yield
        session.after_blocking_call()
    except ShutdownError:
        raise ROSInterruptException("ROS shutdown request") from None


# ----------------------------------------------------------------------------- node and time


def init_node(
    name: str, anonymous: bool = False, log_level: Any = None, disable_signals: bool = False, **_: Any
) -> None:
    """Names the node (once per script: a second call with another name raises ROSException).

    The command line (``sys.argv``) may rename it (``__name:=``), put it in a namespace
    (``__ns:=``), remap names (``from:=to``) and set its private parameters (``_x:=v``).
    An anonymous node keeps its name (rospy would append a unique suffix)."""
    session = current()
    name = str(name).strip("/")
    if not name or "/" in name:
        raise ValueError(f"init_node needs a base name without '/', got {name!r}")
    if session.node_name is not None and session.node_name != name:
        raise ROSException(
            "rospy.init_node() has already been called with different arguments: " + session.node_name
        )
    first = session.node_name is None
    session.node_name = name
    session.names = names.NodeNames.from_argv(sys.argv[1:], name)
    if first:
        for key, value in names.private_params(sys.argv[1:]).items():
            params.put(session.params, session.names.resolve(names.PRIVATE + key), value)
    _log.info("node %s up at t = %.3f s (simulated time)", session.names.caller_id, session.time)


def _node_names() -> names.NodeNames:
    """The running node's names (before ``init_node``: rospy's unnamed node's)."""
    session = current()
    return session.names if session.names is not None else names.NodeNames.from_argv(sys.argv[1:])


def resolve_name(name: str, caller_id: Optional[str] = None) -> str:
    """``name`` resolved for this node (or for ``caller_id``) with the command line's remappings."""
    node = _node_names()
    if caller_id is None:
        return node.resolve(name)
    return names.resolve(name, caller_id, node.remappings)


def get_name() -> str:
    return _node_names().caller_id


def get_caller_id() -> str:
    return get_name()


def get_namespace() -> str:
    return _node_names().namespace


def myargv(argv: Optional[list[str]] = None) -> list[str]:
    """``argv`` (default ``sys.argv``) without the remapping arguments."""
    return names.strip_remaps(sys.argv if argv is None else argv)


def get_time() -> float:
    return current().time


def get_rostime() -> Time:
    return Time.now()


def sleep(duration: Any) -> None:
    """Sleeps ``duration`` (seconds or a Duration) of simulated time; callbacks run meanwhile."""
    seconds = duration.to_sec() if isinstance(duration, Duration) else float(duration)
    if math.isnan(seconds):
        raise ValueError("rospy.sleep: duration is NaN")
    session = current()
    with _blocking():
        session.run_until(session.time + max(0.0, seconds))


class Rate:
    """rospy.Rate: ``sleep()`` keeps a loop at ``hz`` in simulated time."""

    def __init__(self, hz: float, reset: bool = False):
        hz = float(hz)
        if not (hz > 0 and math.isfinite(hz)):
            raise ValueError(f"Rate needs a finite frequency > 0 Hz, got {hz}")
        self.sleep_dur = Duration(1.0 / hz)
        self.last_time = current().time

    def remaining(self) -> Duration:
        return Duration(max(0.0, self.last_time + self.sleep_dur.to_sec() - current().time))

    def sleep(self) -> None:
        session = current()
        period = self.sleep_dur.to_sec()
        end = self.last_time + period
        with _blocking():
            session.run_until(end)
        # Too late by more than a period: start again from now (as rospy does).
        self.last_time = end if session.time - end <= period else session.time


def is_shutdown() -> bool:
    return current().poll_shutdown()


def signal_shutdown(reason: str) -> None:
    current().shutdown(f"signal_shutdown: {reason}")


def on_shutdown(hook: Callable[[], Any]) -> None:
    current().on_shutdown(hook)


def spin() -> None:
    """Runs the callbacks until shutdown (``signal_shutdown`` or ``--timeout``)."""
    session = current()
    try:
        session.run_until(math.inf)
    except ShutdownError:
        return


# ----------------------------------------------------------------------------- parameters


def get_param(name: str, default: Any = KeyError) -> Any:
    """The parameter (or namespace, as a dictionary) at ``name``, a copy as from the
    parameter server; ``default`` when nothing is set there (else KeyError)."""
    key = resolve_name(name)
    try:
        return copy.deepcopy(params.get(current().params, key))
    except KeyError:
        if default is KeyError:
            raise
        return default


def set_param(name: str, value: Any) -> None:
    params.put(current().params, resolve_name(name), copy.deepcopy(value))


def has_param(name: str) -> bool:
    return params.has(current().params, resolve_name(name))


def delete_param(name: str) -> None:
    params.delete(current().params, resolve_name(name))


# ----------------------------------------------------------------------------- topics


def _check_type(topic: str, data_class: Any) -> None:
    session = current()
    source = session.sources.get(topic)
    if source is not None and data_class is not source.msg_class:
        raise ROSException(
            f"topic {topic} has type {source.msg_class._type}, not "
            f"{getattr(data_class, '_type', data_class.__name__)}"
        )
    if source is None and topic not in session.published_topics:
        _log.warning(
            "nothing publishes %s in this cell (yet); the cell's topics: %s",
            topic,
            ", ".join(sorted(session.sources)),
        )


class Subscriber:
    """rospy.Subscriber: ``callback(msg[, callback_args])`` for every message, in time order."""

    def __init__(
        self,
        name: str,
        data_class: Any,
        callback: Optional[Callable[..., Any]] = None,
        callback_args: Any = None,
        queue_size: Optional[int] = None,
        buff_size: int = 65536,
        tcp_nodelay: bool = False,
    ):
        session = current()
        self.name = self.resolved_name = resolve_name(name)
        self.data_class = data_class
        _check_type(self.name, data_class)
        args = () if callback_args is None else (callback_args,)
        self._queue = session.subscribe(self.name, callback, args, queue_size) if callback else None
        if self._queue is not None:
            latched = session.latched.get(self.name)
            if latched is not None:  # a latched topic's last message, to this subscriber only
                self._queue.queue.append(latched)

    def get_num_connections(self) -> int:
        return 1 if self.name in current().sources or self.name in current().published_topics else 0

    def unregister(self) -> None:
        if self._queue is not None:
            current().unsubscribe(self._queue)
            self._queue = None


class Publisher:
    """rospy.Publisher: ``publish(msg)`` (or its fields) reaches the subscribers in order."""

    def __init__(
        self,
        name: str,
        data_class: Any,
        subscriber_listener: Any = None,
        tcp_nodelay: bool = False,
        latch: bool = False,
        headers: Any = None,
        queue_size: Optional[int] = None,
    ):
        session = current()
        self.name = self.resolved_name = resolve_name(name)
        if self.name in session.sources:
            raise ROSException(
                f"{self.name} is published by the cell's {self.name.rsplit('/', 1)[-1]}; "
                "a script cannot publish on it"
            )
        self.data_class = data_class
        self.latch = latch
        session.published_topics.add(self.name)

    def publish(self, *args: Any, **kwargs: Any) -> None:
        if len(args) == 1 and not kwargs and isinstance(args[0], self.data_class):
            message = args[0]
        elif len(args) == 1 and not kwargs and isinstance(args[0], Message):
            raise ROSSerializationException(f"{self.name} takes {self.data_class._type}, got {args[0]._type}")
        else:
            message = self.data_class(*args, **kwargs)
        session = current()
        message = copy.deepcopy(message)
        if self.latch:
            session.latched[self.name] = (session.time, -1, message)
        session.publish(self.name, message)

    def get_num_connections(self) -> int:
        return current().num_subscribers(self.name)

    def unregister(self) -> None:
        current().published_topics.discard(self.name)


def wait_for_message(topic: str, topic_type: Any, timeout: Optional[float] = None) -> Any:
    """The next message on ``topic``; ROSException after ``timeout`` s (simulated)."""
    session = current()
    name = resolve_name(topic)
    _check_type(name, topic_type)
    queue = session.subscribe(name, _read_here, (), 1)
    queue.busy = True  # read below, never delivered as a callback
    if name in session.latched:  # a latched topic's last message answers at once
        queue.queue.append(session.latched[name])
    limit = math.inf if timeout is None else finite_seconds(timeout, "wait_for_message timeout")
    try:
        with _blocking():
            if not session.run_until(session.time + limit, until=lambda: bool(queue.queue)):
                raise ROSException(f"timeout exceeded while waiting for message on topic {name}")
        message = queue.queue[0][2]
    finally:
        session.unsubscribe(queue)
    return message


def _read_here(message: Any) -> None:
    """wait_for_message's queue is read by wait_for_message itself."""


# ----------------------------------------------------------------------------- services


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


# ----------------------------------------------------------------------------- logging


def _emit(level: int, msg: Any, args: tuple) -> None:
    text = str(msg) % args if args else str(msg)
    _log.log(level, "[%s] [t=%.3f] %s", get_name(), current().time, text)


def logdebug(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.DEBUG, msg, args)


def loginfo(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.INFO, msg, args)


def logwarn(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.WARNING, msg, args)


def logerr(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.ERROR, msg, args)


def logfatal(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.CRITICAL, msg, args)


logout = loginfo
logerror = logerr
logwarning = logwarn


def _throttled(level: int) -> Callable[..., None]:
    def log(period: float, msg: Any, *args: Any) -> None:
        session = current()
        key = (level, str(msg))
        last = session.throttle.get(key)
        if last is None or session.time - last >= float(period):
            session.throttle[key] = session.time
            _emit(level, msg, args)

    return log


loginfo_throttle = _throttled(logging.INFO)
logwarn_throttle = _throttled(logging.WARNING)
logerr_throttle = _throttled(logging.ERROR)
logdebug_throttle = _throttled(logging.DEBUG)


def _once(level: int) -> Callable[..., None]:
    def log(msg: Any, *args: Any) -> None:
        session = current()
        key = (level, str(msg))
        if key not in session.throttle:
            session.throttle[key] = session.time
            _emit(level, msg, args)

    return log


loginfo_once = _once(logging.INFO)
logwarn_once = _once(logging.WARNING)
logerr_once = _once(logging.ERROR)
