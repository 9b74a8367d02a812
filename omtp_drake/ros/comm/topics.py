"""rospy's topics (``rospy.topics``): Subscriber, Publisher and ``wait_for_message``.

Names resolve as rospy resolves them (:func:`omtp_drake.ros.comm.client.resolve_name`);
the cell's own sensor topics are :mod:`omtp_drake.ros.gazebo.sensor_topics`. Messages
reach subscribers in publish-time order, one callback at a time
(:mod:`omtp_drake.ros.comm.session`).
"""

from __future__ import annotations

import copy
import logging
import math
from collections.abc import Callable
from typing import Any, Optional

from omtp_drake.errors import check_duration
from omtp_drake.ros.comm.client import get_caller_id, resolve_name
from omtp_drake.ros.comm.exceptions import ROSException, ROSSerializationException
from omtp_drake.ros.comm.messages import Message
from omtp_drake.ros.comm.rostime import _blocking
from omtp_drake.ros.comm.session import current

_log = logging.getLogger("rospy")


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
        self._node = get_caller_id()
        session.registry.add("sub", self.name, self._node, data_class)
        if self._queue is not None:
            latched = session.latched.get(self.name)
            if latched is not None:  # a latched topic's last message, to this subscriber only
                self._queue.queue.append(latched)

    def get_num_connections(self) -> int:
        return 1 if self.name in current().sources or self.name in current().published_topics else 0

    def unregister(self) -> None:
        current().registry.remove("sub", self.name, self._node)
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
        self._node = get_caller_id()
        session.registry.add("pub", self.name, self._node, data_class)

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
        current().registry.remove("pub", self.name, self._node)


def wait_for_message(topic: str, topic_type: Any, timeout: Optional[float] = None) -> Any:
    """The next message on ``topic``; ROSException after ``timeout`` s (simulated)."""
    session = current()
    name = resolve_name(topic)
    _check_type(name, topic_type)
    queue = session.subscribe(name, _read_here, (), 1)
    queue.busy = True  # read below, never delivered as a callback
    if name in session.latched:  # a latched topic's last message answers at once
        queue.queue.append(session.latched[name])
    limit = math.inf if timeout is None else check_duration("wait_for_message timeout", timeout, zero=True)
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
