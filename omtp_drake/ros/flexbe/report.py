"""The report of one ``flexbe-run``: outcome, trace of states, log lines, ledger, times.

``to_dict()`` is the ``--json`` file. Everything but ``wall_time_s`` (and
``replay``) depends only on the behaviour, its parameters, the scenario and its seed.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Optional

from omtp_drake.ros.run.report import ledger_line, settle_line


@dataclass
class FlexbeReport:
    """What one behaviour run did."""

    behavior: str
    scenario: str
    seed: int
    autonomy: str
    #: The behaviour's outcome (``finished``, ``failed``...); None when it did not reach one.
    outcome: Optional[str]
    #: Simulated time at the outcome (or when the run stopped).
    sim_time_s: float
    wall_time_s: float
    #: ``Ledger.to_dict()``: parts per bin, on the floor, held..., once the cell settled.
    ledger: dict[str, Any]
    #: How long (simulated s) the cell ran on after the end before the ledger was taken,
    #: and whether every part rested then (``omtp_drake.ros.run.settling``).
    settle_s: float = 0.0
    at_rest: bool = False
    #: The workspaces whose modules loaded as their 2to3 translation (Python 2, Melodic).
    python2: list[str] = field(default_factory=list)
    #: One entry per state entered: ``{"state": path, "entered", "outcome", "left"}``.
    trace: list[dict[str, Any]] = field(default_factory=list)
    #: FlexBE's Logger lines: ``{"time", "severity", "text"}``.
    logs: list[dict[str, Any]] = field(default_factory=list)
    collisions: list[str] = field(default_factory=list)
    callback_errors: list[str] = field(default_factory=list)
    #: Threads a state started that ended with an exception (``name: Type: message``).
    thread_errors: list[str] = field(default_factory=list)
    #: The error that stopped the run, ``Type: message (at file.py:LINE in f)``.
    exception: Optional[str] = None
    #: The state that raised it (its path), if a state did.
    failed_state: Optional[str] = None
    #: The workspace's frames of that exception's traceback.
    traceback: list[str] = field(default_factory=list)
    #: Why the ROS session shut down (``--timeout``), if it did.
    shutdown: Optional[str] = None
    #: Gazebo plugins of the scenario's models that the cell does not run (one line each).
    ignored_plugins: list[str] = field(default_factory=list)
    #: MoveIt's fixes of a start or goal just outside the joint bounds (its log lines).
    bounds_fixed: list[str] = field(default_factory=list)
    replay: Optional[str] = None
    #: What the error is, as data (:func:`omtp_drake.errors.exception_kind`).
    error: Optional[dict[str, Any]] = None
    #: The session shut down at ``--timeout`` (``shutdown`` says so in words).
    timed_out: bool = False

    @property
    def ok(self) -> bool:
        """The behaviour reached an outcome, without an error, failed callback or collision."""
        return (
            self.outcome is not None
            and self.exception is None
            and not self.callback_errors
            and not self.thread_errors
            and not self.collisions
        )

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def summary(self) -> str:
        lines = [
            f"behaviour {self.behavior!r} on {self.scenario} (seed {self.seed}, autonomy {self.autonomy}): "
            f"outcome {self.outcome or 'none'}; "
            f"{self.sim_time_s:.1f} s simulated in {self.wall_time_s:.1f} s",
            *settle_line(self.settle_s, self.at_rest),
            ledger_line(self.ledger),
        ]
        if self.python2:
            lines.append(f"python 2: {', '.join(self.python2)} loaded as its 2to3 translation (Melodic)")
        lines += ["states:"]
        for entry in self.trace:
            left = f"-> {entry['outcome']} at {entry['left']:.2f} s" if entry["outcome"] else "(no outcome)"
            lines.append(f"  {entry['entered']:8.2f} s  {entry['state']}  {left}")
        lines += [
            f"  [{x['time']:.2f} s] {x['severity']}: {x['text']}"
            for x in self.logs
            if x["severity"] != "debug"
        ]
        lines += [f"collision: {c}" for c in self.collisions]
        lines += [f"bad callback: {c}" for c in self.callback_errors]
        lines += [f"thread error: {c}" for c in self.thread_errors]
        lines += [f"ignored plugin: {p}" for p in self.ignored_plugins]
        lines += [f"moveit bounds: {c}" for c in self.bounds_fixed]
        if self.shutdown:
            lines.append(f"shutdown: {self.shutdown}")
        if self.exception:
            lines += ["traceback (workspace frames, most recent call last):"] + [
                f"  {t}" for t in self.traceback
            ]
            where = f" in state {self.failed_state}" if self.failed_state else ""
            lines.append(f"error{where}: {self.exception}")
        return "\n".join(lines)
