"""A script's threads on the session's simulated clock: one runs at a time.

rospy lets every thread of a script publish, subscribe, call services, read and set
parameters, sleep and look up transforms. The cell has one simulator, so here the
script's threads take turns, as coroutines on simulated time:

- A thread a script thread starts (``threading.Thread(...).start()``, during the run)
  is a *turn*. It runs only while it holds the baton; the thread that holds it hands it
  on only where rospy would block: ``rospy.sleep``, ``Rate.sleep``, ``spin``,
  ``wait_for_message``, ``wait_for_service``, the time a call takes (planning, a
  service), an action's wait, a tf look-up's timeout, between the steps of a MoveIt
  move, and ``Thread.join``.
- At such a point it hands the baton to the turns that are *due*: whose wake-up time
  has come, whose condition holds, or all of them when the session shuts down; the
  earliest wake-up first, then the first started (the script's main thread is first).
  Whoever holds the baton while blocked advances the cell, never past the next
  wake-up. So the same script gives the same run, to the tick.
- ``Thread.join`` between turns waits in simulated time (its ``timeout`` too).
- When the script's main thread ends, its non-daemon threads run on (Python waits for
  them) until they end or the session shuts down. Then each daemon thread gets the
  baton once more: its next blocking call raises ``ROSInterruptException`` and
  ``is_shutdown()`` is True, as at rospy's shutdown; a thread that blocks again after
  that (it swallowed the interrupt) stays where it is, as a daemon thread does when
  Python exits.

A thread's uncaught exception is logged with its traceback and listed in the
report (``thread_errors``); an interrupt at shutdown is its normal end.

Not covered: script threads that wait on each other through ``threading.Event``,
``Lock``, ``Condition`` or ``queue.Queue`` (only ``join``), and a thread that loops
without any ROS call (``while True: pass``; ``while not rospy.is_shutdown()`` is
fine, polling lets time pass): the thread keeps the baton and the run stands still.
Threads that libraries start from other threads are not turns.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
import threading
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any, Optional, Protocol

_log = logging.getLogger("rospy")

#: Times closer than this (s) are the same time.
_EPS = 1e-9


class Clock(Protocol):
    """What the turns need of the session: its time, its shutdown, its blocking wait."""

    @property
    def time(self) -> float: ...

    shutdown_reason: Optional[str]
    thread_errors: list[str]

    def run_until(self, t_end: float, until: Optional[Callable[[], bool]] = None) -> bool: ...


@dataclass(eq=False)
class _Turn:
    """One script thread: its place in the order and what it waits for."""

    thread: threading.Thread
    order: int
    daemon: bool
    go: threading.Event = field(default_factory=threading.Event)
    #: Due from this simulated time on, or as soon as ``until()`` holds.
    wake_at: float = -math.inf
    until: Optional[Callable[[], bool]] = None
    ended: bool = False
    #: Told to stop (the script's end): its next blocking call raises, ``is_shutdown()`` is True.
    stopping: bool = False
    #: That call raised; a blocking call after it freezes the thread.
    interrupted: bool = False
    #: Blocked again after it was interrupted: it never runs again.
    frozen: bool = False


class ScriptThreads:
    """The turns of one run's script threads (see the module doc).

    Args:
        clock: the session.
        interrupts: the exceptions that end a thread normally at shutdown.
    """

    def __init__(self, clock: Clock, interrupts: tuple[type[BaseException], ...]):
        self._clock = clock
        self._interrupts = interrupts
        self._turns: dict[threading.Thread, _Turn] = {}
        self._order = itertools.count()
        self._open = False

    # ------------------------------------------------------------ the baton

    def _mine(self) -> Optional[_Turn]:
        return self._turns.get(threading.current_thread()) if self._open else None

    def _waiting(self, me: Optional[_Turn]) -> list[_Turn]:
        return [t for t in self._turns.values() if t is not me and not (t.ended or t.frozen)]

    def _due(self, turn: _Turn) -> bool:
        if turn.stopping or self._clock.shutdown_reason is not None:
            return True
        return self._clock.time >= turn.wake_at - _EPS or (turn.until is not None and turn.until())

    @staticmethod
    def _hand_to(me: _Turn, other: _Turn) -> None:
        """Gives ``other`` the baton; returns when ``me`` has it again."""
        other.go.set()
        me.go.wait()
        me.go.clear()

    def pass_on(self, wake_at: float, until: Optional[Callable[[], bool]] = None) -> bool:
        """A blocking point of the calling thread: the turns due run first (it waits for
        ``wake_at`` or ``until()``, meanwhile). Returns whether any ran."""
        me = self._mine()
        if me is None:
            return False
        if me.stopping:
            if me.interrupted:
                self._freeze(me)
            return False  # its caller raises (stop_here)
        if len(self._turns) < 2:
            return False
        due = self._next(me, due_only=True)
        if due is None:
            return False
        me.wake_at, me.until = wake_at, until
        self._hand_to(me, due)
        me.wake_at, me.until = -math.inf, None
        return True

    def _next(self, me: Optional[_Turn], *, due_only: bool) -> Any:
        """The turn to run next: the due one with the earliest (wake-up, start), else
        (unless ``due_only``) the earliest one waiting; None if none."""
        waiting = self._waiting(me)
        due = [t for t in waiting if self._due(t)]
        pool = due or ([] if due_only else waiting)
        return min(pool, key=lambda t: (t.wake_at, t.order), default=None)

    def next_wake(self) -> float:
        """The earliest wake-up time after now of the turns waiting (inf: none)."""
        now = self._clock.time
        me = self._mine()
        times = [t.wake_at for t in self._waiting(me) if t.wake_at > now + _EPS]
        return min(times, default=math.inf)

    def told_to_stop(self) -> bool:
        """The calling thread was told to stop (the script ended)."""
        me = self._mine()
        return me is not None and me.stopping

    def stop_here(self) -> bool:
        """At a blocking point: True once when the calling thread was told to stop (the
        caller raises rospy's interrupt); a thread that blocks again after that is frozen
        here, as a daemon thread is when Python exits (this never returns then)."""
        me = self._mine()
        if me is None or not me.stopping:
            return False
        if me.interrupted:
            self._freeze(me)
        me.interrupted = True
        return True

    def _freeze(self, me: _Turn) -> None:
        me.frozen = True
        following = self._next(me, due_only=False)
        if following is not None:
            following.go.set()
        threading.Event().wait()

    # ------------------------------------------------------------ threads

    @contextlib.contextmanager
    def running(self) -> Iterator[None]:
        """The calling thread is the script's main thread for the block: threads it (or
        they) start are turns; at the end, the rest as in the module doc."""
        me = _Turn(threading.current_thread(), next(self._order), daemon=False)
        self._turns[me.thread] = me
        self._open = True
        start, join = threading.Thread.start, threading.Thread.join
        threading.Thread.start = self._start(start)  # type: ignore[method-assign,assignment]
        threading.Thread.join = self._join(join)  # type: ignore[method-assign]
        try:
            yield
        finally:
            try:
                self._wait_for(lambda: not any(not t.daemon for t in self._waiting(me)), math.inf)
                self._stop_daemons(me)
            finally:
                threading.Thread.start = start  # type: ignore[method-assign]
                threading.Thread.join = join  # type: ignore[method-assign]
                self._open = False

    def _start(self, start: Callable[[threading.Thread], None]) -> Callable[[threading.Thread], None]:
        def gated_start(thread: threading.Thread) -> None:
            if self._mine() is None:
                start(thread)  # a thread no script thread starts: not a turn
                return
            turn = _Turn(thread, next(self._order), daemon=thread.daemon, wake_at=self._clock.time)
            self._turns[thread] = turn
            thread.run = self._gated_run(turn, thread.run)  # type: ignore[method-assign]
            start(thread)

        return gated_start

    def _gated_run(self, turn: _Turn, run: Callable[[], None]) -> Callable[[], None]:
        def gated_run() -> None:
            turn.go.wait()
            turn.go.clear()
            try:
                if not turn.stopping:
                    run()
            except BaseException as e:
                self._record(turn, e)
            finally:
                turn.ended = True
                following = self._next(turn, due_only=False)
                if following is not None:
                    following.go.set()

        return gated_run

    def _record(self, turn: _Turn, error: BaseException) -> None:
        if isinstance(error, self._interrupts) and (turn.stopping or self._clock.shutdown_reason):
            return  # rospy's interrupt at shutdown: the thread's normal end
        if isinstance(error, SystemExit):
            return  # SystemExit raised in a thread ends that thread only, silently
        name = turn.thread.name
        _log.error("Exception in thread %s:\n%s", name, "".join(traceback.format_exception(error)))
        self._clock.thread_errors.append(f"{name}: {type(error).__name__}: {' '.join(str(error).split())}")

    def _join(self, join: Callable[..., None]) -> Callable[..., None]:
        def gated_join(thread: threading.Thread, timeout: Optional[float] = None) -> None:
            target = self._turns.get(thread)
            if self._mine() is None or target is None:
                join(thread, timeout)
                return
            if thread is threading.current_thread():
                raise RuntimeError("cannot join current thread")
            limit = math.inf if timeout is None else self._clock.time + max(0.0, float(timeout))
            self._wait_for(lambda: target.ended, limit)
            if target.ended:
                join(thread)  # its last lines, after it handed the baton on

        return gated_join

    def _wait_for(self, done: Callable[[], bool], limit: float) -> None:
        """Waits in simulated time until ``done()`` or ``limit``; after a shutdown, the
        other turns run (and end) in order."""
        me = self._mine()
        while not done() and self._clock.time < limit - _EPS:
            if self._clock.shutdown_reason is None and not (me is not None and me.stopping):
                with contextlib.suppress(*self._interrupts):
                    self._clock.run_until(limit, until=done)
                continue
            other = self._next(me, due_only=False)
            if other is None or me is None:
                return
            self._hand_to(me, other)

    def _stop_daemons(self, me: _Turn) -> None:
        """Each thread still waiting is told to stop and runs until it ends or blocks."""
        for turn in sorted(self._waiting(me), key=lambda t: t.order):
            turn.stopping = True
            self._hand_to(me, turn)
