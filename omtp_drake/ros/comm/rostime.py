"""rospy's time (``rospy.rostime``, ``rospy.timer``): the cell's simulated time.

``Time.now()`` and ``get_time()`` read the session's simulated clock; ``sleep`` and
``Rate.sleep`` advance it (callbacks run meanwhile, see
:mod:`omtp_drake.ros.comm.session`). Every blocking call runs inside :func:`_blocking`: a
shutdown (``signal_shutdown``, ``--timeout``) becomes :class:`ROSInterruptException`,
as in rospy. The time a call itself takes (planning, a service round trip) is
:mod:`omtp_drake.ros.comm.latency`'s.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from typing import Any

from omtp_drake.ros.comm import messages
from omtp_drake.ros.comm.exceptions import ROSInterruptException
from omtp_drake.ros.comm.messages import Duration
from omtp_drake.ros.comm.session import ShutdownError, current


class Time(messages.Time):
    """rospy.Time: genpy's Time and ``now()``, the cell's simulated time."""

    __slots__ = ()

    @classmethod
    def now(cls) -> Time:
        return cls(0, int(round(current().time * 1e9)))


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
