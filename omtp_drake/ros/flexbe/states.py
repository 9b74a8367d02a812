"""``flexbe_states``: the states FlexBE ships, with FlexBE's parameters, keys and outcomes.

Headless runs have no operator: :class:`OperatorDecisionState` returns its
suggested outcome (the transition's autonomy level still applies) and stops the
run with :class:`~omtp_drake.ros.flexbe.context.OperatorRequired` when it has none;
:class:`InputState` always needs an operator and stops the run the same way.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Optional

from omtp_drake.ros.comm.client import resolve_name
from omtp_drake.ros.comm.messages import Bool, Empty, String
from omtp_drake.ros.flexbe.context import OperatorRequired, current_run
from omtp_drake.ros.flexbe.engine import EventState, Logger
from omtp_drake.ros.flexbe.proxies import ProxyPublisher, ProxySubscriberCached
from omtp_drake.ros.flexbe.topics import get_topic_class


class LogState(EventState):
    """Logs ``text`` with ``severity`` when entered; ``done``."""

    def __init__(self, text: str, severity: int = Logger.REPORT_HINT):
        super().__init__(outcomes=["done"])
        self._text, self._severity = text, severity

    def on_enter(self, userdata: Any) -> None:
        Logger.log(self._text, self._severity)

    def execute(self, userdata: Any) -> Optional[str]:
        return "done"


class LogKeyState(EventState):
    """Logs ``text.format(data)`` when entered; input key ``data``; ``done``."""

    def __init__(self, text: str, severity: int = Logger.REPORT_HINT):
        super().__init__(outcomes=["done"], input_keys=["data"])
        self._text, self._severity = text, severity

    def on_enter(self, userdata: Any) -> None:
        Logger.log(self._text.format(userdata.data), self._severity)

    def execute(self, userdata: Any) -> Optional[str]:
        return "done"


class WaitState(EventState):
    """``done`` once more than ``wait_time`` seconds (simulated) have passed since entering."""

    def __init__(self, wait_time: float):
        super().__init__(outcomes=["done"])
        self._wait = float(wait_time)
        self._start = 0.0

    def on_enter(self, userdata: Any) -> None:
        self._start = current_run().time

    def execute(self, userdata: Any) -> Optional[str]:
        return "done" if current_run().time - self._start > self._wait else None


class DecisionState(EventState):
    """The outcome ``str(conditions(input_value))`` when it is one of ``outcomes``; else stays."""

    def __init__(self, outcomes: list[str], conditions: Callable[[Any], Any]):
        super().__init__(outcomes=outcomes, input_keys=["input_value"])
        self._conditions = conditions

    def execute(self, userdata: Any) -> Optional[str]:
        if self._conditions is None:
            return None
        try:
            outcome = str(self._conditions(userdata.input_value))
        except Exception as e:
            Logger.logwarn(f"Passed no function as predicate!\n{e}")
            return None
        return outcome if outcome in self.outcomes else None


class _Calculation(EventState):
    """``output_value`` computed by ``calculation`` when entered (from the userdata by :meth:`_calculate`);
    ``done``. FlexBE's warnings when there is no calculation or it raises."""

    def __init__(self, calculation: Callable[..., Any], input_keys: list[str]):
        super().__init__(outcomes=["done"], input_keys=input_keys, output_keys=["output_value"])
        self._calculation = calculation
        self._result: Any = None

    def _calculate(self, userdata: Any) -> Any:
        raise NotImplementedError

    def on_enter(self, userdata: Any) -> None:
        if self._calculation is None:
            Logger.logwarn("Passed no calculation!")
            return
        try:
            self._result = self._calculate(userdata)
        except Exception as e:
            Logger.logwarn(f"Failed to execute calculation function!\n{e}")

    def execute(self, userdata: Any) -> Optional[str]:
        userdata.output_value = self._result
        return "done"


class CalculationState(_Calculation):
    """``output_value = calculation(input_value)`` (computed when entered); ``done``."""

    def __init__(self, calculation: Callable[[Any], Any]):
        super().__init__(calculation, ["input_value"])

    def _calculate(self, userdata: Any) -> Any:
        return self._calculation(userdata.input_value)


class FlexibleCalculationState(_Calculation):
    """``output_value = calculation(**{key: userdata[key]})`` over ``input_keys``; ``done``."""

    def __init__(self, calculation: Callable[..., Any], input_keys: list[str]):
        super().__init__(calculation, input_keys)

    def _calculate(self, userdata: Any) -> Any:
        return self._calculation(**{key: userdata[key] for key in self.input_keys})


class CheckConditionState(EventState):
    """``true`` or ``false`` as ``predicate(input_value)`` (evaluated when entered)."""

    def __init__(self, predicate: Callable[[Any], Any]):
        super().__init__(outcomes=["true", "false"], input_keys=["input_value"])
        self._predicate = predicate
        self._outcome = "false"

    def on_enter(self, userdata: Any) -> None:
        try:
            self._outcome = "true" if self._predicate(userdata.input_value) else "false"
        except Exception as e:
            Logger.logwarn(f"Failed to execute condition function!\n{e}")

    def execute(self, userdata: Any) -> Optional[str]:
        return self._outcome


class FlexibleCheckConditionState(EventState):
    """``true`` or ``false`` as ``predicate([userdata[k] for k in input_keys])``."""

    def __init__(self, predicate: Callable[[list], Any], input_keys: list[str]):
        super().__init__(outcomes=["true", "false"], input_keys=input_keys)
        self._predicate = predicate
        self._outcome = "false"

    def on_enter(self, userdata: Any) -> None:
        try:
            self._outcome = "true" if self._predicate([userdata[k] for k in self.input_keys]) else "false"
        except Exception as e:
            Logger.logwarn(f"Failed to execute condition function!\n{e}")

    def execute(self, userdata: Any) -> Optional[str]:
        return self._outcome


class UserDataState(EventState):
    """Puts ``data`` into output key ``data``; ``done``."""

    def __init__(self, data: Any):
        super().__init__(outcomes=["done"], output_keys=["data"])
        self._data = data

    def execute(self, userdata: Any) -> Optional[str]:
        userdata.data = self._data
        return "done"


class SubscriberState(EventState):
    """The last message on ``topic`` into output key ``message``: ``received`` (at once
    when not ``blocking``), ``unavailable`` when nothing publishes ``topic``; ``clear``
    drops a message that arrived before the state was entered."""

    def __init__(self, topic: str, blocking: bool = True, clear: bool = False):
        super().__init__(outcomes=["received", "unavailable"], output_keys=["message"])
        self._topic, self._blocking, self._clear = topic, blocking, clear
        self._connected = False
        self._sub: Optional[ProxySubscriberCached] = None
        if not self._connect():
            Logger.logwarn(
                f"Topic {topic} for state {self.name} not yet available.\n"
                "Will try again when entering the state..."
            )

    def _connect(self) -> bool:
        msg_class, found, _ = get_topic_class(resolve_name(self._topic))
        if msg_class is None or found is None:
            return False
        self._sub = ProxySubscriberCached({self._topic: msg_class})
        self._connected = True
        return True

    def on_enter(self, userdata: Any) -> None:
        if not self._connected:
            if self._connect():
                Logger.loginfo(f"Successfully subscribed to previously unavailable topic {self._topic}")
            else:
                Logger.logwarn(f"Topic {self._topic} still not available, giving up.")
        if self._connected and self._clear and self._sub is not None and self._sub.has_msg(self._topic):
            self._sub.remove_last_msg(self._topic)

    def execute(self, userdata: Any) -> Optional[str]:
        if not self._connected or self._sub is None:
            userdata.message = None
            return "unavailable"
        if self._sub.has_msg(self._topic) or not self._blocking:
            userdata.message = self._sub.get_last_msg(self._topic)
            self._sub.remove_last_msg(self._topic)
            return "received"
        return None


class _PublisherState(EventState):
    _msg_class: Any = Empty

    def __init__(self, topic: str, input_keys: tuple[str, ...] = ()):
        super().__init__(outcomes=["done"], input_keys=list(input_keys))
        self._topic = topic
        self._pub = ProxyPublisher({topic: self._msg_class})

    def execute(self, userdata: Any) -> Optional[str]:
        return "done"


class PublisherStringState(_PublisherState):
    """Publishes input key ``value`` as std_msgs/String on ``topic``; ``done``."""

    _msg_class = String

    def __init__(self, topic: str):
        super().__init__(topic, ("value",))

    def on_enter(self, userdata: Any) -> None:
        self._pub.publish(self._topic, String(data=userdata.value))


class PublisherBoolState(_PublisherState):
    """Publishes input key ``value`` as std_msgs/Bool on ``topic``; ``done``."""

    _msg_class = Bool

    def __init__(self, topic: str):
        super().__init__(topic, ("value",))

    def on_enter(self, userdata: Any) -> None:
        self._pub.publish(self._topic, Bool(data=bool(userdata.value)))


class PublisherEmptyState(_PublisherState):
    """Publishes std_msgs/Empty on ``topic``; ``done``."""

    def __init__(self, topic: str):
        super().__init__(topic)

    def on_enter(self, userdata: Any) -> None:
        self._pub.publish(self._topic, Empty())


class OperatorDecisionState(EventState):
    """Returns ``suggestion`` (if given); a decision without one needs an operator."""

    def __init__(self, outcomes: list[str], hint: Optional[str] = None, suggestion: Optional[str] = None):
        super().__init__(outcomes=outcomes)
        self._hint, self._suggestion = hint, suggestion

    def on_enter(self, userdata: Any) -> None:
        if self._hint is not None:
            Logger.loghint(self._hint)
        if self._suggestion is None or self._suggestion not in self.outcomes:
            raise OperatorRequired(
                f"OperatorDecisionState {self.path} waits for an operator to choose one of "
                f"{', '.join(self.outcomes)} (no suggestion among them); flexbe-run has no operator"
            )

    def execute(self, userdata: Any) -> Optional[str]:
        return self._suggestion


class InputState(EventState):
    """An operator's input (FlexBE's input GUI): not available headless."""

    def __init__(self, request: int, message: str):
        super().__init__(
            outcomes=["received", "aborted", "no_connection", "data_error"], output_keys=["data"]
        )
        self._request, self._message = request, message

    def on_enter(self, userdata: Any) -> None:
        raise OperatorRequired(
            f"InputState {self.path} asks the operator for input (request type {self._request}: "
            f"{self._message!r}); flexbe-run has no operator (FlexBE's input GUI)"
        )

    def execute(self, userdata: Any) -> Optional[str]:
        return None
