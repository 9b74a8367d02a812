"""One ROS-style run on a cell: simulated time, topics, callbacks, shutdown.

A :class:`Session` wraps a :class:`~omtp_drake.Cell` for the ROS names a script
imports (``rospy``, ``moveit_commander``...). Those names find it with
:func:`current` (ROS's client libraries are process-global too; the session is
set for the duration of one script by :func:`active`).

Time. Simulated time moves only inside blocking calls (``rospy.sleep``,
``Rate.sleep``, ``spin``, ``wait_for_message``, MoveIt moves, and the time planning
and service calls take: :attr:`Session.latency`, :mod:`omtp_drake.ros.comm.latency`).
:meth:`Session.run_until` advances the cell in ticks and, between ticks,
delivers the messages published so far to their subscribers' callbacks; a
blocking MoveIt move delivers them between its steps (``Cell.on_move_step``),
as rospy's callback threads run while the main thread waits for MoveIt.

Callbacks. The cell's sensor topics (logical cameras, break beam) publish into
the subscribers' queues from the cell's tick (at the sensor's own rate: a camera
message per new image, stamped with the image's time); a script's Publisher
publishes at once. Delivery is in publish-time order across subscribers, one
callback at a time, never re-entrant: while a subscriber's callback runs (and
moves the arm, say) its own messages wait in its queue, the oldest dropped
beyond ``queue_size`` as in rospy, and other subscribers' messages wait too.
A callback that raises is logged with its traceback and recorded (rospy's
"bad callback"), and delivery goes on.

Threads. A script's own threads take turns with its main thread at those blocking
calls, in simulated-time order (:mod:`omtp_drake.ros.comm.threads`, :attr:`Session.threads`):
one runs at a time, so the cell is stepped by one thread at a time.
"""

from __future__ import annotations

import collections
import contextlib
import itertools
import logging
import math
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.errors import NotSupportedError
from omtp_drake.ros.comm.current import CurrentStack
from omtp_drake.ros.comm.graph import GraphRegistry
from omtp_drake.ros.comm.threads import ScriptThreads

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell, RosLatencyConfig
    from omtp_drake.ros.comm.names import NodeNames
    from omtp_drake.ros.gazebo.cell_services import Service
    from omtp_drake.ros.gazebo.sensor_topics import Source
    from omtp_drake.ros.moveit.joint_limits import JointLimits
    from omtp_drake.ros.moveit.srdf import SemanticModel

_log = logging.getLogger("rospy")

#: Polls of ``is_shutdown`` without simulated time moving after which one tick
#: passes: a busy-wait loop lets time flow, as wall time flows under ROS.
BUSY_POLLS_PER_TICK = 100

_SESSIONS: CurrentStack[Session] = CurrentStack(
    "no ROS session: the ROS names of omtp_drake work inside "
    "`omtp-drake ros-run SCRIPT.py --scenario NAME` (or omtp_drake.ros.run_script)"
)


class ShutdownError(Exception):
    """Raised inside the session when it shuts down during a blocking call
    (rospy turns it into ROSInterruptException)."""


def current() -> Session:
    """The session of the running script (a clear error outside ``ros-run``)."""
    return _SESSIONS.current()


def active(session: Session) -> contextlib.AbstractContextManager[Session]:
    """Makes ``session`` the current one for the ``with`` block."""
    return _SESSIONS.active(session)


@dataclass(eq=False)
class SubscriberQueue:
    """One subscriber: its topic, callback and queue of (stamp, order, message)."""

    topic: str
    callback: Callable[..., Any]
    callback_args: tuple
    queue: collections.deque = field(default_factory=collections.deque)
    busy: bool = False
    active: bool = True


def _cell_graph(cell: Cell) -> tuple[dict[str, Source], dict[str, Service]]:
    """The topics of ``cell``'s logical cameras (no services yet), as the course's Gazebo
    plugin names them; tf's camera frames follow the models the camera topics list. The
    other plugins' topics and services (joint states, beam, grippers, belt) come with
    Gazebo (:mod:`omtp_drake.ros.gazebo.plugin_topics`)."""
    from omtp_drake.ros.comm._core import camera_views
    from omtp_drake.ros.gazebo.sensor_topics import cell_sources

    views = camera_views(cell)
    cell.tf.use_images(lambda camera: views[camera].image_of)
    return cell_sources(cell, views), {}


def _as_node(session: Session, callback: Callable[..., Any]) -> Callable[..., Any]:
    """``callback`` run as the node starting in ``session`` now (its name and how it
    resolves names), whenever it is called later."""
    node = session.node_name, session.names

    def as_node(*args: Any) -> Any:
        saved = session.node_name, session.names
        session.node_name, session.names = node
        try:
            return callback(*args)
        finally:
            session.node_name, session.names = saved

    return as_node


class Session:
    """The ROS graph of one script on ``cell`` (see the module doc).

    Args:
        cell: the cell the script runs on.
        timeout: simulated seconds after which the session shuts down (None: never).
        moveit: ``noetic`` or ``melodic`` (the shape of ``MoveGroupCommander.plan``).
        latency: the simulated time calls take (None: the scenario's ``ros_latency``).
    """

    def __init__(
        self,
        cell: Cell,
        *,
        timeout: Optional[float] = None,
        moveit: str = "noetic",
        latency: Optional[RosLatencyConfig] = None,
    ):
        from omtp_drake.ros.gazebo.world_plugins import attach_gazebo

        self.cell = cell
        self.timeout = timeout
        self.moveit = moveit
        self.latency = cell.scenario.ros_latency if latency is None else latency
        self.node_name: Optional[str] = None
        #: How the script's node resolves names (set by ``init_node``; see omtp_drake.ros.comm.names).
        self.names: Optional[NodeNames] = None
        #: A launch's node is starting (ros-run runs it up to its ``spin``, which returns at
        #: once then; its subscribers, timers and services stay in the session).
        self.starting_node = False
        self.shutdown_reason: Optional[str] = None
        #: The session shut down because ``timeout`` was reached (not for another reason).
        self.timed_out = False
        self.callback_errors: list[str] = []
        #: The script's threads that ended with an exception (``name: Type: message``).
        self.thread_errors: list[str] = []
        self.threads = ScriptThreads(self, (ShutdownError, KeyboardInterrupt))
        self.collisions: list[str] = []
        #: MoveIt's fixes of a start or goal outside the joint bounds (omtp_drake.ros.moveit.bounds).
        self.bounds_fixed: list[str] = []
        self._subscribers: dict[str, list[SubscriberQueue]] = collections.defaultdict(list)
        self._order = itertools.count()
        self._in_callback = 0
        self._busy_polls = 0
        self._last_poll_time = -1.0
        #: Spawner calls that spawned nothing (their warnings).
        self.empty_spawn_calls: list[str] = []
        self.sources, self.services = _cell_graph(cell)
        self.gazebo = attach_gazebo(self)  # Gazebo's own topics and services, and the spawner
        self._on_shutdown: list[Callable[[], Any]] = []
        #: Recorders of every message published (``on_message(topic, stamp, message)``, ``close()``:
        #: a ``--bag``, omtp_drake.ros.bag.session), closed when the run ends.
        self.taps: list[Any] = []
        #: The parameter server, topics scripts publish, latched messages, log throttles.
        self.params: dict[str, Any] = {}
        self.published_topics: set[str] = set()
        #: The scripts' publishers and subscribers, by node (the master's view: .graph).
        self.registry = GraphRegistry()
        self.latched: dict[str, Any] = {}
        self.throttle: dict[tuple, float] = {}
        #: MoveIt's config of the run (omtp_drake.ros.moveit.config.install): the SRDF's
        #: semantics and the joint_limits.yaml limits (None: the arms' own).
        self.semantic: Optional[SemanticModel] = None
        self.joint_limits: Optional[JointLimits] = None
        #: id(RobotTrajectory) -> (it, its fingerprint, the plan): recent plans, run exactly.
        self.plans: collections.OrderedDict[int, tuple] = collections.OrderedDict()
        cell.runtime.on_tick(lambda _rt: self._poll_sources())
        cell.on_move_step(self._between_move_steps)
        cell.limit_move_steps(self.threads.next_wake)  # other threads wake on time during a move

    # ------------------------------------------------------------ time

    @property
    def time(self) -> float:
        return self.cell.time

    @property
    def tick(self) -> float:
        return self.cell.runtime.tick

    def _between_move_steps(self) -> None:
        """While a blocking move goes on: the callbacks due, then the other threads due."""
        self.deliver(self.time)
        self.threads.pass_on(self.time)
        if self.threads.stop_here():
            raise ShutdownError("the script ended")

    def think(self, seconds: float) -> None:
        """A blocking call's own time (planning, a service round trip): ``seconds`` of
        simulated time pass, unless Gazebo's physics is paused, when the call takes wall
        time only and the simulated clock stands still."""
        if seconds > 0 and self.gazebo.clock_stopped() is None:
            self.run_until(self.time + seconds)

    def run_until(self, t_end: float, until: Optional[Callable[[], bool]] = None) -> bool:
        """Advances to ``t_end`` (callbacks delivered between ticks), or until
        ``until()`` holds (checked after each delivery); returns whether it held.
        Raises ShutdownError if the session is or becomes shut down."""
        if self.starting_node:
            raise NotSupportedError(
                "a launch's node waits or sleeps before rospy.spin(); ros-run starts a launch's nodes "
                "one after another up to their spin(), so a node's loop must run in its callbacks or timers"
            )
        while True:
            self.check_running()
            self.deliver(t_end)
            self.check_running()
            if until is not None and until():
                return True
            if self.time >= t_end - 1e-9:
                return False
            if self.threads.pass_on(t_end, until):
                continue  # other threads ran: time, messages and shutdown may have changed
            paused = self.gazebo.clock_stopped()
            if paused is not None:
                self.shutdown(paused)
                self.check_running()
            step_end = min(t_end, self.time + self.tick, self.threads.next_wake())
            if self.timeout is not None and step_end >= self.timeout - 1e-9:
                self.cell.runtime.advance_to(max(self.time, min(step_end, self.timeout)))
                self._time_out()
                self.check_running()
            self.cell.runtime.advance_to(step_end)

    def after_blocking_call(self) -> None:
        """What every blocking call ends with: the timeout, then the callbacks due."""
        if self.timeout is not None and self.time >= self.timeout - 1e-9:
            self._time_out()
        if self.shutdown_reason is None:
            self.deliver(self.time)

    def check_running(self) -> None:
        if self.threads.stop_here():  # first: a thread told to stop is frozen at its next block
            raise ShutdownError(self.shutdown_reason or "the script ended")
        if self.shutdown_reason is not None:
            raise ShutdownError(self.shutdown_reason)

    def poll_shutdown(self) -> bool:
        """``rospy.is_shutdown()``: delivers the callbacks due; after
        BUSY_POLLS_PER_TICK polls without time moving, lets one tick pass."""
        if self.threads.told_to_stop():
            return True
        if self.shutdown_reason is None:
            if self.time != self._last_poll_time:
                self._last_poll_time, self._busy_polls = self.time, 0
            self._busy_polls += 1
            if self._busy_polls >= BUSY_POLLS_PER_TICK and not self._in_callback:
                self._busy_polls = 0
                with contextlib.suppress(ShutdownError):
                    self.run_until(self.time + self.tick)
            else:
                self.deliver(self.time)
        return self.shutdown_reason is not None

    def _time_out(self) -> None:
        """Shuts the session down at ``timeout`` (``timed_out`` records it as data)."""
        if self.shutdown_reason is None:
            self.timed_out = True
        self.shutdown(f"--timeout of {self.timeout:g} s simulated time reached")

    def shutdown(self, reason: str) -> None:
        if self.shutdown_reason is None:
            self.shutdown_reason = reason
            _log.info("shutdown request: %s", reason)
            for hook in self._on_shutdown:
                hook()

    def close_taps(self) -> None:
        """Closes the recorders (the run has ended)."""
        for tap in self.taps:
            tap.close()

    def on_shutdown(self, hook: Callable[[], Any]) -> None:
        self._on_shutdown.append(hook)

    # ------------------------------------------------------------ topics

    def subscribe(
        self, topic: str, callback: Callable[..., Any], callback_args: tuple, queue_size
    ) -> SubscriberQueue:
        if queue_size is not None and (int(queue_size) != queue_size or queue_size < 0):
            raise ValueError(f"queue_size must be None or an integer >= 0, got {queue_size!r}")
        maxlen = None if queue_size in (None, 0) else int(queue_size)
        if self.starting_node:
            callback = _as_node(self, callback)
        subscriber = SubscriberQueue(topic, callback, callback_args, collections.deque(maxlen=maxlen))
        self._subscribers[topic].append(subscriber)
        self.gazebo.on_subscribe(topic)
        return subscriber

    def unsubscribe(self, subscriber: SubscriberQueue) -> None:
        subscriber.active = False
        subscriber.queue.clear()
        if subscriber in self._subscribers[subscriber.topic]:
            self._subscribers[subscriber.topic].remove(subscriber)

    def subscribed_topics(self) -> list[str]:
        """The topics with a subscriber (a script's or the cell's own)."""
        return [topic for topic, subscribers in self._subscribers.items() if subscribers]

    def num_subscribers(self, topic: str) -> int:
        return len(self._subscribers.get(topic, []))

    def publish(self, topic: str, message: Any, stamp: Optional[float] = None) -> None:
        """Queues ``message`` for every subscriber of ``topic`` (delivered in time order)."""
        stamp = self.time if stamp is None else stamp
        order = next(self._order)
        for tap in self.taps:
            tap.on_message(topic, stamp, message)
        for subscriber in self._subscribers.get(topic, []):
            subscriber.queue.append((stamp, order, message))

    def _poll_sources(self) -> None:
        for topic, source in self.sources.items():
            if self._subscribers.get(topic) or source.latch:
                for stamp, message in source.poll():
                    self.publish(topic, message, stamp)
                    if source.latch:
                        self.latched[topic] = (stamp, -1, message)

    def deliver(self, until: float = math.inf) -> None:
        """Runs the callbacks of the queued messages, earliest first, one at a time,
        while simulated time is at most ``until`` (the blocking call that delivers
        returns when its time is up; the rest run at the next blocking call)."""
        if self._in_callback:
            return  # never re-entrant: the running callback's caller delivers the rest
        while self.shutdown_reason is None and self.time <= until + 1e-9:
            ready = [s for subs in self._subscribers.values() for s in subs if s.queue and not s.busy]
            if not ready:
                return
            subscriber = min(ready, key=lambda s: s.queue[0][:2])
            _stamp, _order, message = subscriber.queue.popleft()
            self._run_callback(subscriber, message)

    def _run_callback(self, subscriber: SubscriberQueue, message: Any) -> None:
        subscriber.busy = True
        self._in_callback += 1
        try:
            subscriber.callback(message, *subscriber.callback_args)
        except ShutdownError:
            pass
        except Exception as e:
            if isinstance(e, KeyboardInterrupt) and self.shutdown_reason is not None:
                return  # rospy's ROSInterruptException at shutdown: the callback's normal end
            text = "".join(traceback.format_exception(e))
            _log.error("bad callback: %s\n%s", subscriber.callback, text)
            self.callback_errors.append(f"{subscriber.topic}: {type(e).__name__}: {e}")
        finally:
            self._in_callback -= 1
            subscriber.busy = False
