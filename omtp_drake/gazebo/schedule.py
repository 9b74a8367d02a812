"""When a plugin publishes: the one periodic scheduler of the layer, and a publication
(a topic, its neutral message type and how to poll it) as both transports take it.

A transport polls every publication once per step of the cell, with the simulated time
``t`` the step reached; a poll returns the messages that became due since the last one
(each carries its own stamp). A ``lazy`` publication is polled only while the topic has
a subscriber (rendering costs; Gazebo's camera plugins are lazy too), so its samples
while nobody listens are not made at all.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

#: Time (s) within which a due time counts as reached (float steps of 10 ms).
EPS = 1e-9

T = TypeVar("T")


class Periodic(Generic[T]):
    """``make(t)`` every ``period`` s of simulated time: at the first poll at or after
    each due time, stamped with the poll's time; the next due time is a period after
    the last one (or the poll's time, when polls were late), so a rate above the
    cell's step rate gives one message per step, as a Gazebo plugin updating at most
    once per world update does."""

    def __init__(self, period: float, make: Callable[[float], T]):
        self.period = float(period)
        self._make = make
        self._next = 0.0

    def __call__(self, t: float) -> list[T]:
        if t < self._next - EPS:
            return []
        self._next = max(self._next + self.period, t)
        return [self._make(t)]


class Sampled(Generic[T]):
    """``make(stamp)`` once per sample of a sensor at ``rate`` Hz: the first poll at or
    after sample k's time ``k / rate`` makes it, stamped ``k / rate`` (the sensor's
    measurement time, as Gazebo's sensors stamp their data)."""

    def __init__(self, rate: float, make: Callable[[float], T]):
        self.period = 1.0 / float(rate)
        self._make = make
        self._last = -1

    def __call__(self, t: float) -> list[T]:
        index = int(t / self.period + 1e-6)
        if index <= self._last:
            return []
        self._last = index
        return [self._make(index * self.period)]


@dataclass(frozen=True)
class Publication:
    """A topic a plugin publishes: its name as gazebo_ros gives it (a transport may
    rename it; see docs/ros2.md), its neutral message type, its poll (see the module
    doc) and whether it is polled only while subscribed."""

    topic: str
    message: type
    poll: Callable[[float], list[Any]]
    lazy: bool = False
    #: The plugin that publishes it (for logs and the transports' tables).
    plugin: str = ""
    #: A late subscriber gets the last message (ROS 1's latch, ROS 2's transient local).
    latched: bool = False


@dataclass(frozen=True)
class Subscription:
    """A topic a plugin subscribes to: its name, the neutral message type the transport
    converts each message to, and the plugin's callback (called on the cell's thread)."""

    topic: str
    message: type
    callback: Callable[[Any], object]
    plugin: str = ""


def topic(namespace: str, name: str) -> str:
    """``/<namespace>/<name>`` with one slash between parts (gazebo_ros's node namespace)."""
    return "/" + "/".join(p for p in (*namespace.split("/"), *name.split("/")) if p)
