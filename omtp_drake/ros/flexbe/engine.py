"""FlexBE's state machine engine: EventState, OperatableStateMachine, Autonomy, Logger.

The semantics are FlexBE's (``flexbe_core`` of ROS 1 Noetic):

- A state machine is built in a ``with`` block: ``OperatableStateMachine.add(label,
  state, transitions, autonomy, remapping)``; the first state added is the initial
  one; every transition target is a label or an outcome of the container.
- Executing a state machine executes its current state once. An
  :class:`EventState` gets ``on_enter`` when entered, ``execute`` on every tick
  (returning ``None`` stays), ``on_exit`` when it returns an outcome; ``on_start``
  and ``on_stop`` when the behaviour starts and stops.
- Each state ticks at its rate (10 Hz unless ``set_rate``), in the run's clock:
  the container sleeps until its current state's next tick (``rospy.Rate``:
  a state entered late executes at once and again one period later).
- Autonomy: an outcome whose required level (``Autonomy.Off``... ``Full``) is not
  below the run's level needs an operator's confirmation. A headless run has no
  operator: it stops with :class:`OperatorRequired` naming the state and outcome.
- A state that raises: FlexBE logs "Failed to execute state" and waits for an
  operator; a headless run logs the same and stops with :class:`StateFailed`.
- Userdata: see :mod:`omtp_drake.ros.flexbe.userdata`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar, Optional

from omtp_drake.errors import SimulationError
from omtp_drake.ros.flexbe.context import DEFAULT_RATE_HZ, OperatorRequired, StateFailed, current_run
from omtp_drake.ros.flexbe.userdata import StateError, StateMachineError, UserData

#: FlexBE's name of the outcome every state machine may take when preempted.
PREEMPTED = "preempted"


class Autonomy:
    """The autonomy an outcome requires (FlexBE's levels)."""

    Inherit = 0
    Off = 0
    Low = 1
    High = 2
    Full = 3


def _logging_at(severity: int, local: bool = False) -> Callable[..., None]:
    """A ``Logger.log*`` function: ``text % args`` (``text`` alone without args) at
    ``severity``, through :meth:`Logger.log` or, ``local``, :meth:`Logger.local`."""

    def log_at(text: Any, *args: Any) -> None:
        message = str(text) % args if args else str(text)
        (Logger.local if local else Logger.log)(message, severity)

    return log_at


class Logger:
    """FlexBE's behaviour logger: lines with a severity, in the run's report."""

    REPORT_INFO = 0
    REPORT_WARN = 1
    REPORT_HINT = 2
    REPORT_ERROR = 3
    REPORT_DEBUG = 10

    @staticmethod
    def log(text: Any, severity: int) -> None:
        current_run().log(str(text), int(severity))

    @staticmethod
    def local(text: Any, severity: int) -> None:
        current_run().log(str(text), int(severity))

    logdebug = staticmethod(_logging_at(REPORT_DEBUG))
    loginfo = staticmethod(_logging_at(REPORT_INFO))
    logwarn = staticmethod(_logging_at(REPORT_WARN))
    loghint = staticmethod(_logging_at(REPORT_HINT))
    logerr = staticmethod(_logging_at(REPORT_ERROR))
    localinfo = staticmethod(_logging_at(REPORT_INFO, local=True))
    localdebug = staticmethod(_logging_at(REPORT_DEBUG, local=True))


def _unique(keys: Any) -> list[str]:
    out: list[str] = []
    for key in keys or ():
        if key not in out:
            out.append(key)
    return out


def _now_or_none() -> Optional[float]:
    try:
        return current_run().time
    except SimulationError:
        return None


class State:
    """A state: outcomes, input and output keys, a name and parent once added, a rate."""

    def __init__(self, *args: Any, **kwargs: Any):
        io_keys = list(kwargs.get("io_keys", []))
        self._outcomes = _unique(kwargs.get("outcomes", []))
        self._input_keys = _unique(list(kwargs.get("input_keys", [])) + io_keys)
        self._output_keys = _unique(list(kwargs.get("output_keys", [])) + io_keys)
        self._name: Optional[str] = None
        self._parent: Optional[OperatableStateMachine] = None
        self._flexbe_period = 1.0 / DEFAULT_RATE_HZ
        #: The start of the state's current period (``rospy.Rate``'s: its construction).
        self._flexbe_last_tick: Optional[float] = _now_or_none()

    @property
    def outcomes(self) -> list[str]:
        return self._outcomes

    @property
    def input_keys(self) -> list[str]:
        return self._input_keys

    @property
    def output_keys(self) -> list[str]:
        return self._output_keys

    @property
    def name(self) -> Optional[str]:
        return self._name

    def set_name(self, value: str) -> None:
        if self._name is not None:
            raise StateError("Cannot change the name of a state!")
        self._name = value

    @property
    def parent(self) -> Optional[OperatableStateMachine]:
        return self._parent

    def set_parent(self, value: OperatableStateMachine) -> None:
        if self._parent is not None:
            raise StateError("Cannot change the parent of a state!")
        self._parent = value

    @property
    def path(self) -> str:
        return "" if self._parent is None else f"{self._parent.path}/{self._name}"

    def set_rate(self, rate: float) -> None:
        """The rate (Hz) of this state's ``execute`` calls."""
        rate = float(rate)
        if not rate > 0:
            raise ValueError(f"set_rate needs a rate > 0 Hz, got {rate}")
        self._flexbe_period = 1.0 / rate

    @property
    def sleep_duration(self) -> float:
        """Seconds until this state's next tick (0 when due)."""
        if self._flexbe_last_tick is None:
            return 0.0
        return max(0.0, self._flexbe_last_tick + self._flexbe_period - current_run().time)

    def sleep(self) -> None:
        """``rospy.Rate.sleep`` in the run's clock: until one period after the last tick,
        or not at all (and the period restarts now) when more than a period late."""
        run = current_run()
        if self._flexbe_last_tick is not None and run.time < self._flexbe_last_tick + self._flexbe_period:
            run.clock.advance_to(self._flexbe_last_tick + self._flexbe_period)
        self._flexbe_count_tick()

    def _flexbe_count_tick(self) -> None:
        """Starts the next period (``rospy.Rate``: from the due time, or from now when
        more than a period late)."""
        now = current_run().time
        if self._flexbe_last_tick is None:
            self._flexbe_last_tick = now
            return
        end = self._flexbe_last_tick + self._flexbe_period
        self._flexbe_last_tick = end if now - end <= self._flexbe_period else now

    def execute(self, userdata: UserData) -> Optional[str]:
        return None

    def _flexbe_start(self) -> None:
        """The behaviour starts (containers pass it on)."""

    def _flexbe_stop(self) -> None:
        """The behaviour stops (containers pass it on)."""


class EventState(State):
    """FlexBE's EventState: override ``execute`` and the ``on_*`` events."""

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._entering = True

    def on_start(self) -> None:
        """Once when the behaviour starts."""

    def on_stop(self) -> None:
        """Once when the behaviour stops."""

    def on_enter(self, userdata: UserData) -> None:
        """Each time the state becomes active."""

    def on_exit(self, userdata: UserData) -> None:
        """Each time the state returns an outcome."""

    def on_pause(self) -> None:
        """An operator paused the behaviour (never in a headless run)."""

    def on_resume(self, userdata: UserData) -> None:
        """An operator resumed the behaviour (never in a headless run)."""

    def _flexbe_tick(self, userdata: UserData) -> Optional[str]:
        if self._entering:
            self._entering = False
            self.on_enter(userdata)
        return self.execute(userdata)

    def _flexbe_leave(self, userdata: UserData) -> None:
        self._entering = True
        self.on_exit(userdata)

    def _flexbe_start(self) -> None:
        self.on_start()

    def _flexbe_stop(self) -> None:
        self.on_stop()


class OperatableStateMachine(State):
    """FlexBE's state machine: states added in a ``with`` block, userdata, autonomy."""

    _opened: ClassVar[list[OperatableStateMachine]] = []

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._states: list[State] = []
        self._labels: dict[str, State] = {}
        self._transitions: dict[str, dict[str, str]] = {}
        self._remappings: dict[str, dict[str, str]] = {}
        self._autonomy: dict[str, dict[str, int]] = {}
        self._current: Optional[State] = None
        self._flexbe_entry: Any = None
        self._own_userdata = UserData()
        self._userdata: Optional[UserData] = None

    # ------------------------------------------------------------ building

    def __enter__(self) -> OperatableStateMachine:
        OperatableStateMachine._opened.append(self)
        return self

    def __exit__(self, *exc: Any) -> None:
        OperatableStateMachine._opened.remove(self)

    @staticmethod
    def add(
        label: str,
        state: State,
        transitions: dict[str, str],
        autonomy: Optional[dict[str, int]] = None,
        remapping: Optional[dict[str, str]] = None,
    ) -> None:
        """Adds ``state`` as ``label`` to the state machine of the ``with`` block."""
        if not OperatableStateMachine._opened:
            raise StateMachineError("No container openend, activate one first by: 'with state_machine:'")
        self = OperatableStateMachine._opened[-1]
        if label in self._labels:
            raise StateMachineError(f"The label {label} has already been added to this state machine!")
        if label in self._outcomes:
            raise StateMachineError(f"The label {label} is an outcome of this state machine!")
        if not isinstance(state, State):
            raise StateMachineError(f"{label}: {state!r} is no FlexBE state")
        transitions = dict(transitions)
        transitions.setdefault(PREEMPTED, PREEMPTED)
        self._states.append(state)
        self._labels[label] = state
        self._transitions[label] = transitions
        self._autonomy[label] = dict(autonomy or {})
        self._remappings[label] = dict(remapping or {})
        state.set_name(label)
        state.set_parent(self)

    def __contains__(self, label: str) -> bool:
        return label in self._labels

    def __getitem__(self, label: str) -> State:
        return self._labels[label]

    def __iter__(self) -> Any:
        return iter(state.name for state in self._states)

    @property
    def userdata(self) -> UserData:
        return self._own_userdata

    @property
    def initial_state(self) -> State:
        if not self._states:
            raise StateMachineError(f"state machine {self.path or '/'} has no states")
        return self._states[0]

    @property
    def current_state(self) -> State:
        if self._current is None:
            raise StateMachineError("No state active!")
        return self._current

    @property
    def current_state_label(self) -> Optional[str]:
        return self.current_state.name

    def get_deep_state(self) -> Optional[State]:
        state = self._current
        while isinstance(state, OperatableStateMachine):
            state = state._current
        return state

    def assert_consistent_transitions(self) -> None:
        valid = [*self._labels, *self._outcomes, PREEMPTED]
        for label, transitions in self._transitions.items():
            for outcome, target in transitions.items():
                if target not in valid:
                    raise StateMachineError(
                        f"Transition target '{target}' of {label} > {outcome} missing in {valid}"
                    )

    # ------------------------------------------------------------ running

    def execute(self, userdata: Optional[UserData] = None) -> Optional[str]:
        if self._current is None:
            self.assert_consistent_transitions()
            self._current = self.initial_state
            self._userdata = userdata if userdata is not None else UserData()
            self._userdata.add_from(self._own_userdata)
        return self._execute_current_state()

    def _view(self, state: State) -> UserData:
        return UserData(
            reference=self._userdata,
            input_keys=state.input_keys,
            output_keys=state.output_keys,
            remap=self._remappings[state.name or ""],
        )

    def _execute_current_state(self) -> Optional[str]:
        state = self.current_state
        label = state.name or ""
        run = current_run()
        if self._flexbe_entry is None or self._flexbe_entry.path != state.path:
            self._flexbe_entry = run.enter(state.path)
        outcome = self._run_state(state)
        if outcome is None:
            return None
        self._flexbe_entry.outcome, self._flexbe_entry.left = outcome, run.time
        self._flexbe_entry = None
        target = self._transitions[label][outcome]
        self._current = self._labels.get(target)
        return target if self._current is None else None

    def _run_state(self, state: State) -> Optional[str]:
        """One tick of ``state`` in its userdata view; its checked outcome."""
        label = state.name or ""
        try:
            with self._view(state) as userdata:
                if isinstance(state, EventState):
                    outcome = state._flexbe_tick(userdata)
                    if outcome is not None:
                        self._check_outcome(state, outcome)
                        state._flexbe_leave(userdata)
                else:
                    outcome = state.execute(userdata)
                    if outcome is not None:
                        self._check_outcome(state, outcome)
        except (StateFailed, OperatorRequired):
            raise
        except Exception as e:
            Logger.logerr(f"Failed to execute state {label}:\n{e}")
            raise StateFailed(state.path, e) from e
        return outcome

    def _check_outcome(self, state: State, outcome: Any) -> None:
        label = state.name or ""
        if outcome not in self._transitions[label]:
            raise StateError(
                f"Returned outcome '{outcome}' is not registered as transition! "
                f"({label}'s transitions: {', '.join(self._transitions[label])})"
            )
        required = self._autonomy[label].get(outcome, -1)
        level = current_run().autonomy
        if isinstance(state, EventState) and not required < level:
            names = {0: "Off", 1: "Low", 2: "High", 3: "Full"}
            raise OperatorRequired(
                f"state {state.path} returned '{outcome}', which needs autonomy "
                f"{names.get(required, required)} ({required}) to pass without an operator; this run's "
                f"autonomy is {level} and there is no operator to confirm it (run with a higher "
                "--autonomy, e.g. full)"
            )

    def sleep(self) -> None:
        if self._current is not None:
            self._current.sleep()

    @property
    def sleep_duration(self) -> float:
        return self._current.sleep_duration if self._current is not None else 0.0

    def spin(self, userdata: Optional[UserData] = None) -> str:
        """Executes until the state machine returns an outcome (FlexBE's ``spin``)."""
        while True:
            outcome = self.execute(userdata)
            if outcome is not None:
                return outcome
            self.sleep()

    def on_exit(self, userdata: UserData) -> None:
        """Leaves the current state (a concurrency container ending its branches)."""
        state = self._current
        if state is not None:
            with self._view(state) as view:
                if isinstance(state, EventState):
                    state._flexbe_leave(view)
                elif isinstance(state, OperatableStateMachine):
                    state.on_exit(view)
            self._current = None
            self._flexbe_entry = None

    def _flexbe_start(self) -> None:
        for state in self._states:
            state._flexbe_start()

    def _flexbe_stop(self) -> None:
        for state in self._states:
            state._flexbe_stop()

    def confirm(self, name: str, behavior_id: int = 0) -> None:
        """Names the top-level state machine and starts its states (``on_start``)."""
        self._name = self._name or name
        self._flexbe_start()

    def destroy(self) -> None:
        """Stops its states (``on_stop``)."""
        self._flexbe_stop()
