"""FlexBE's proxies (``flexbe_core.proxy``) on the ROS session of the run.

As in FlexBE, every proxy of a run shares one subscriber, publisher, service
client and action client per topic (the caches live in the
:class:`~omtp_drake.ros.flexbe.context.FlexbeRun`). Subscribers keep the last
message (and, buffered, all messages in order); messages arrive as simulated
time passes between the behaviour's ticks. Services and actions are the cell's
(``/gripperN/control``, ``/omtp/conveyor/control``, ``/start_spawn``...,
``/compute_ik``; the ``/move_group`` and ``execute_trajectory`` actions). A
service or action that does not exist is logged as FlexBE does ("timed out"),
naming the ones that do, and calling it raises ValueError.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Optional

from omtp_drake.ros.comm import exceptions, service
from omtp_drake.ros.comm import topics as rospy_topics
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.flexbe.context import current_run
from omtp_drake.ros.flexbe.engine import Logger
from omtp_drake.ros.tf.listener import TransformListener


def _set_up_each(topics: Optional[dict[str, Any]], set_up: Callable[..., None], *options: Any) -> None:
    """A proxy's constructor: ``set_up(topic, msg_type, *options)`` for each ``{topic: msg_type}``."""
    for topic, msg_type in (topics or {}).items():
        set_up(topic, msg_type, *options)


def _share(cache: dict[str, Any], topic: str, make: Callable[[], Any]) -> bool:
    """Puts ``make()`` in the run's ``cache`` under ``topic`` unless one is there (all proxies of
    a run share one per topic); whether it made one."""
    if topic in cache:
        return False
    cache[topic] = make()
    return True


class ProxySubscriberCached:
    """Subscribes topics and caches their last message (and a buffer on request)."""

    def __init__(self, topics: Optional[dict[str, Any]] = None):
        _set_up_each(topics, self.subscribe)

    @staticmethod
    def _topics() -> dict[str, dict[str, Any]]:
        return current_run().subscribers

    def subscribe(self, topic: str, msg_type: Any, callback: Any = None, buffered: bool = False) -> None:
        topics = self._topics()
        _share(topics, topic, lambda: self._entry(topic, msg_type, buffered))
        if callback is not None:
            topics[topic]["callbacks"].append(callback)

    def _entry(self, topic: str, msg_type: Any, buffered: bool) -> dict[str, Any]:
        """A topic's cache entry: its last message, buffer, callbacks and subscriber."""
        entry: dict[str, Any] = {"last_msg": None, "buffered": buffered, "msg_queue": [], "callbacks": []}
        entry["subscriber"] = rospy_topics.Subscriber(topic, msg_type, self._callback, topic)
        return entry

    def _callback(self, msg: Any, topic: str) -> None:
        entry = self._topics().get(topic)
        if entry is None:
            return
        entry["last_msg"] = msg
        if entry["buffered"]:
            entry["msg_queue"].append(msg)
        for callback in entry["callbacks"]:
            callback(msg)

    def set_callback(self, topic: str, callback: Any) -> None:
        self._topics()[topic]["callbacks"].append(callback)

    def enable_buffer(self, topic: str) -> None:
        self._topics()[topic]["buffered"] = True

    def disable_buffer(self, topic: str) -> None:
        entry = self._topics()[topic]
        entry["buffered"], entry["msg_queue"] = False, []

    def is_available(self, topic: str) -> bool:
        return topic in self._topics()

    has_topic = is_available

    def get_last_msg(self, topic: str) -> Any:
        return self._topics()[topic]["last_msg"]

    def get_from_buffer(self, topic: str) -> Any:
        entry = self._topics()[topic]
        if not entry["buffered"]:
            Logger.logwarn("Attempted to access buffer of non-buffered topic!")
        return entry["msg_queue"].pop(0) if entry["msg_queue"] else None

    def has_msg(self, topic: str) -> bool:
        entry = self._topics().get(topic)
        return entry is not None and entry["last_msg"] is not None

    def has_buffered(self, topic: str) -> bool:
        return bool(self._topics()[topic]["msg_queue"])

    def remove_last_msg(self, topic: str, clear_buffer: bool = False) -> None:
        if topic in current_run().persistent_topics:
            return
        entry = self._topics()[topic]
        entry["last_msg"] = None
        if clear_buffer:
            entry["msg_queue"] = []

    def make_persistant(self, topic: str) -> None:
        current_run().persistent_topics.add(topic)

    make_persistent = make_persistant

    def unsubscribe_topic(self, topic: str) -> None:
        entry = self._topics().pop(topic, None)
        if entry is not None:
            entry["subscriber"].unregister()

    def shutdown(self) -> None:
        for topic in list(self._topics()):
            self.unsubscribe_topic(topic)


class ProxyPublisher:
    """Publishers by topic, shared by all states."""

    def __init__(self, topics: Optional[dict[str, Any]] = None, _latch: bool = False, _queue_size: int = 100):
        _set_up_each(topics, self.createPublisher, _latch, _queue_size)

    def createPublisher(  # noqa: N802 (FlexBE's name)
        self, topic: str, msg_type: Any, _latch: bool = False, _queue_size: int = 100
    ) -> None:
        _share(
            current_run().publishers,
            topic,
            lambda: rospy_topics.Publisher(topic, msg_type, latch=_latch, queue_size=_queue_size),
        )

    def is_available(self, topic: str) -> bool:
        return topic in current_run().publishers

    def publish(self, topic: str, msg: Any) -> None:
        publisher = current_run().publishers.get(topic)
        if publisher is None:
            Logger.logwarn(f"ProxyPublisher: topic {topic} not yet registered!")
            return
        publisher.publish(msg)

    def wait_for_any(self, topic: str, timeout: float = 5.0) -> bool:
        publisher = current_run().publishers.get(topic)
        return publisher is not None and publisher.get_num_connections() > 0


class ProxyServiceCaller:
    """Service clients by name; ``call(topic, request)``."""

    def __init__(
        self, topics: Optional[dict[str, Any]] = None, persistent: bool = False, wait_duration: float = 10
    ):
        _set_up_each(topics, self.setupService, persistent, wait_duration)

    def setupService(  # noqa: N802 (FlexBE's name)
        self, topic: str, msg_type: Any, persistent: bool = False, wait_duration: float = 10
    ) -> None:
        if _share(current_run().services, topic, lambda: service.ServiceProxy(topic, msg_type, persistent)):
            self._check_service_available(topic)

    def is_available(self, topic: str) -> bool:
        return self._check_service_available(topic)

    def call(self, topic: str, request: Any) -> Any:
        if not self._check_service_available(topic):
            raise ValueError(f"Cannot call service client {topic}: Topic not available.")
        return current_run().services[topic].call(request)

    def _check_service_available(self, topic: str) -> bool:
        client = current_run().services.get(topic)
        if client is None:
            Logger.logerr(f"Service client {topic} not yet registered, need to add it first!")
            return False
        try:
            service.wait_for_service(client.resolved_name)
        except exceptions.ROSException:
            services = ", ".join(sorted(current().services)) or "none"
            Logger.logerr(f"Service client {topic} timed out! (this cell's services: {services})")
            return False
        return True


class ProxyActionClient:
    """Action clients by name: ``send_goal(topic, goal)``, then ``has_result`` / ``get_result``."""

    def __init__(self, topics: Optional[dict[str, Any]] = None, wait_duration: float = 10):
        _set_up_each(topics, self.setupClient, wait_duration)

    def setupClient(self, topic: str, msg_type: Any, wait_duration: float = 10) -> None:  # noqa: N802
        _share(current_run().actions, topic, lambda: self._new_client(topic, msg_type))

    @staticmethod
    def _new_client(topic: str, msg_type: Any) -> Any:
        """The action client of ``topic``, or None (logged as FlexBE's time-out) when the cell has none."""
        from omtp_drake.errors import NotSupportedError
        from omtp_drake.ros.moveit.actions import SimpleActionClient
        from omtp_drake.ros.moveit.move_group import MoveGroupClient, is_move_group

        try:
            return (
                MoveGroupClient(topic)
                if is_move_group(topic, msg_type)
                else SimpleActionClient(topic, msg_type)
            )
        except NotSupportedError as e:
            Logger.logerr(f"Action client {topic} timed out! ({e})")
            return None

    def _client(self, topic: str) -> Any:
        client = current_run().actions.get(topic)
        if client is None:
            raise ValueError(f"Cannot send goal for action client {topic}: Topic not available.")
        return client

    def send_goal(self, topic: str, goal: Any) -> None:
        client = self._client(topic)
        run = current_run()
        run.action_results[topic] = None
        run.action_feedback[topic] = None
        client.send_goal(goal)

    def is_available(self, topic: str) -> bool:
        return current_run().actions.get(topic) is not None

    def _done(self, topic: str) -> bool:
        client = current_run().actions.get(topic)
        if client is None:
            return False
        done = client.is_done() if hasattr(client, "is_done") else _trajectory_done(client)
        if done and current_run().action_results.get(topic) is None:
            current_run().action_results[topic] = client.get_result()
        return done

    def has_result(self, topic: str) -> bool:
        self._done(topic)
        return current_run().action_results.get(topic) is not None

    def get_result(self, topic: str) -> Any:
        self._done(topic)
        return current_run().action_results.get(topic)

    def remove_result(self, topic: str) -> None:
        current_run().action_results[topic] = None

    def has_feedback(self, topic: str) -> bool:
        return current_run().action_feedback.get(topic) is not None

    def get_feedback(self, topic: str) -> Any:
        return current_run().action_feedback.get(topic)

    def remove_feedback(self, topic: str) -> None:
        current_run().action_feedback[topic] = None

    def get_state(self, topic: str) -> int:
        return self._client(topic).get_state()

    def is_active(self, topic: str) -> bool:
        return not self._done(topic) and current_run().actions.get(topic) is not None

    def cancel(self, topic: str) -> None:
        self._client(topic).cancel_goal()

    def get_goal_status_text(self, topic: str) -> str:
        client = current_run().actions.get(topic)
        if client is None:
            return f"Failed to get status text: Invalid action topic = [{topic}]"
        return client.get_goal_status_text() if hasattr(client, "get_goal_status_text") else ""


def _trajectory_done(client: Any) -> bool:
    """Whether an ``execute_trajectory`` goal has ended (its motion's end has passed)."""
    from omtp_drake.ros.moveit.actions import GoalStatus

    if client.get_state() == GoalStatus.ACTIVE and current().time >= client._end - 1e-9:
        client.wait_for_result()  # at its end already: marks it succeeded, no time passes
    return client.get_state() not in (GoalStatus.ACTIVE, GoalStatus.LOST)


class ProxyTransformListener:
    """FlexBE's shared tf listener: ``listener()`` is ROS 1 tf's TransformListener
    (:class:`omtp_drake.ros.tf.listener.TransformListener`) on the cell's frames."""

    def __init__(self) -> None:
        run = current_run()
        if run.transform_listener is None:
            run.transform_listener = TransformListener()

    def listener(self) -> Any:
        return current_run().transform_listener
