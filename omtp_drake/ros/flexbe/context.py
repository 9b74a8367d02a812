"""One FlexBE run: its clock, autonomy level, trace of states, log lines and proxies.

FlexBE's onboard engine keeps these process-wide (class attributes of its
proxies and state machines). Here they belong to a :class:`FlexbeRun`, made
current for the duration of one behaviour with :func:`active_run`; the names a
behaviour imports (``flexbe_core``, ``flexbe_states``) find it with
:func:`current_run`.

Time is the run's clock: :class:`SessionClock` (the ROS session's simulated
time, advanced by ticking the cell) under ``flexbe-run``, or
:class:`ManualClock` (time jumps, nothing else runs) for the engine alone.
"""

from __future__ import annotations

import contextlib
import logging
from dataclasses import dataclass, field
from typing import Any, Optional, Protocol

from omtp_drake.errors import SimulationError
from omtp_drake.ros.comm.current import CurrentStack

_log = logging.getLogger("flexbe")

#: FlexBE's rate of a state's ``execute`` calls (Hz), unless the state sets another.
DEFAULT_RATE_HZ = 10.0

#: FlexBE's autonomy levels by name (``--autonomy``); a transition whose required
#: level is below the run's level is taken without an operator.
AUTONOMY_LEVELS = {"off": 0, "low": 1, "high": 2, "full": 3}

#: Logger severities (flexbe_msgs/BehaviorLog) and their names in the report.
SEVERITY_NAMES = {0: "info", 1: "warn", 2: "hint", 3: "error", 10: "debug"}


class Clock(Protocol):
    @property
    def time(self) -> float: ...

    def advance_to(self, t: float) -> None: ...


class ManualClock:
    """Time that only moves when the engine sleeps (engine tests, no cell)."""

    def __init__(self, start: float = 0.0):
        self._time = float(start)

    @property
    def time(self) -> float:
        return self._time

    def advance_to(self, t: float) -> None:
        self._time = max(self._time, float(t))


class SessionClock:
    """The ROS session's simulated time: sleeping runs the cell and delivers callbacks."""

    def __init__(self, session: Any):
        self._session = session

    @property
    def time(self) -> float:
        return float(self._session.time)

    def advance_to(self, t: float) -> None:
        self._session.run_until(t)


@dataclass
class TraceEntry:
    """A state of the behaviour: its path, when it was entered and left with which outcome."""

    path: str
    entered: float
    outcome: Optional[str] = None
    left: Optional[float] = None

    def to_dict(self) -> dict[str, Any]:
        return {"state": self.path, "entered": self.entered, "outcome": self.outcome, "left": self.left}


@dataclass
class LogLine:
    time: float
    severity: str
    text: str

    def to_dict(self) -> dict[str, Any]:
        return {"time": self.time, "severity": self.severity, "text": self.text}


class OperatorRequired(SimulationError):
    """The behaviour waits for an operator (an outcome above the autonomy level, an
    input request); ``flexbe-run`` has none, so the run stops here."""


class StateFailed(Exception):
    """A state (or a container's bookkeeping) raised: FlexBE logs it and waits for an
    operator; a headless run stops with it. ``path`` is the state's path."""

    def __init__(self, path: str, error: BaseException):
        super().__init__(f"state {path}: {type(error).__name__}: {error}")
        self.path = path
        self.error = error


@dataclass(eq=False)
class FlexbeRun:
    """What one behaviour run shares: clock, autonomy, trace, logs and proxy caches."""

    clock: Clock
    autonomy: int = AUTONOMY_LEVELS["full"]
    trace: list[TraceEntry] = field(default_factory=list)
    logs: list[LogLine] = field(default_factory=list)
    #: The path of the priority container running alone (FlexBE's ``active_container``).
    priority_path: Optional[str] = None
    #: Proxy caches by topic (FlexBE shares them between all states of a behaviour).
    subscribers: dict[str, dict[str, Any]] = field(default_factory=dict)
    persistent_topics: set[str] = field(default_factory=set)
    publishers: dict[str, Any] = field(default_factory=dict)
    services: dict[str, Any] = field(default_factory=dict)
    actions: dict[str, Any] = field(default_factory=dict)
    action_results: dict[str, Any] = field(default_factory=dict)
    action_feedback: dict[str, Any] = field(default_factory=dict)
    transform_listener: Any = None
    #: The workspaces' packages (``rospkg``): name -> folder.
    packages: dict[str, Any] = field(default_factory=dict)

    @property
    def time(self) -> float:
        return self.clock.time

    def log(self, text: str, severity: int) -> None:
        name = SEVERITY_NAMES.get(severity, f"level {severity}")
        self.logs.append(LogLine(self.time, name, text))
        level = {"warn": logging.WARNING, "error": logging.ERROR, "debug": logging.DEBUG}.get(
            name, logging.INFO
        )
        _log.log(level, "[t=%.3f] %s%s", self.time, "Behavior Hint: " if name == "hint" else "", text)

    def enter(self, path: str) -> TraceEntry:
        entry = TraceEntry(path, self.time)
        self.trace.append(entry)
        return entry


_RUNS: CurrentStack[FlexbeRun] = CurrentStack(
    "no FlexBE run: flexbe_core works inside `omtp-drake flexbe-run BEHAVIOR --workspace DIR "
    "--scenario NAME` (or omtp_drake.ros.flexbe.run_behavior, or "
    "omtp_drake.ros.flexbe.context.active_run)"
)


def current_run() -> FlexbeRun:
    """The running behaviour's run (a clear error outside one)."""
    return _RUNS.current()


def active_run(run: FlexbeRun) -> contextlib.AbstractContextManager[FlexbeRun]:
    """Makes ``run`` the current one for the ``with`` block."""
    return _RUNS.active(run)
