"""The report of one ``ros-run``: times, the ledger, collisions, the script's exception.

``to_dict()`` is the ``--json`` file: ``{"ledger": <the ledger as in run's JSON>,
"sim_time_s", "wall_time_s", "exception", ...}``. Everything but
``wall_time_s`` (and ``replay``) depends only on the script, its arguments, the
scenario and its seed.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Optional, Protocol


@dataclass
class RosReport:
    """What one script run did."""

    script: str
    scenario: str
    seed: int
    #: Simulated time at the script's end.
    sim_time_s: float
    wall_time_s: float
    #: ``Ledger.to_dict()``: parts per bin, on the floor, held..., once the cell settled.
    ledger: dict[str, Any]
    #: How long (simulated s) the cell ran on after the end before the ledger was taken,
    #: and whether every part rested then (``omtp_drake.ros.run.settling``).
    settle_s: float = 0.0
    at_rest: bool = False
    #: Moves stopped by the collision guard (their messages).
    collisions: list[str] = field(default_factory=list)
    #: Callbacks that raised (``topic: Type: message``); rospy logs and goes on.
    callback_errors: list[str] = field(default_factory=list)
    #: The script's threads that ended with an exception (``name: Type: message``).
    thread_errors: list[str] = field(default_factory=list)
    #: The script's uncaught exception, ``Type: message (at script.py:LINE in f)``.
    exception: Optional[str] = None
    #: The script's own frames of that exception's traceback.
    traceback: list[str] = field(default_factory=list)
    #: Why the ROS session shut down (``signal_shutdown``, ``--timeout``), if it did.
    shutdown: Optional[str] = None
    #: The script's ``sys.exit`` code (0 when it ended normally).
    exit_code: int = 0
    #: The script is Python 2 (ROS Melodic) and ran as its 2to3 translation.
    python2: bool = False
    #: Spawner calls that spawned nothing (the course's spawner stays silent; each was logged).
    empty_spawn_calls: list[str] = field(default_factory=list)
    #: Gazebo plugins of the scenario's models that the cell does not run (one line each).
    ignored_plugins: list[str] = field(default_factory=list)
    #: MoveIt's fixes of a start or goal just outside the joint bounds (its log lines).
    bounds_fixed: list[str] = field(default_factory=list)
    replay: Optional[str] = None
    #: What the script's exception is, as data (:func:`omtp_drake.errors.exception_kind`).
    error: Optional[dict[str, Any]] = None
    #: The session shut down at ``--timeout`` (``shutdown`` says so in words).
    timed_out: bool = False

    @property
    def ok(self) -> bool:
        """The script ended without an exception, a failed callback or thread, a collision
        or a failing exit code."""
        return (
            self.exception is None
            and not self.callback_errors
            and not self.thread_errors
            and not self.collisions
            and self.exit_code == 0
        )

    @property
    def in_bins(self) -> int:
        """Parts in any bin at the end."""
        return sum(self.ledger["in_bin"].values())

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def summary(self) -> str:
        lines = [
            f"{self.script} on {self.scenario} (seed {self.seed}): {self.sim_time_s:.1f} s simulated "
            f"in {self.wall_time_s:.1f} s",
            *settle_line(self.settle_s, self.at_rest),
            ledger_line(self.ledger),
        ]
        if self.python2:
            lines.append("python 2: the script ran as its 2to3 translation (Melodic)")
        lines += [f"collision: {c}" for c in self.collisions]
        lines += [f"bad callback: {c}" for c in self.callback_errors]
        lines += [f"thread error: {c}" for c in self.thread_errors]
        lines += [f"spawn call: {c}" for c in self.empty_spawn_calls]
        lines += [f"ignored plugin: {p}" for p in self.ignored_plugins]
        lines += [f"moveit bounds: {c}" for c in self.bounds_fixed]
        if self.shutdown:
            lines.append(f"shutdown: {self.shutdown}")
        if self.exception:
            lines += ["script traceback (most recent call last):"] + [f"  {t}" for t in self.traceback]
            lines.append(f"exception: {self.exception}")
        return "\n".join(lines)


def ledger_line(ledger: dict[str, Any]) -> str:
    """``parts: spawned N; in bins: ...; on floor ..., held ..., disposed ...``: where a
    run's parts are (``Ledger.to_dict()``), as the ROS commands' reports print it."""
    bins = ", ".join(f"{k} {v}" for k, v in ledger["in_bin"].items()) or "no bins"
    return (
        f"parts: spawned {ledger['spawned']}; in bins: {bins}; on floor {ledger['on_floor']}, "
        f"on belt {ledger['on_belt']}, elsewhere {ledger['elsewhere']}, held {sum(ledger['held'].values())}, "
        f"disposed {ledger['disposed']}"
    )


def settle_line(settle_s: float, at_rest: bool) -> list[str]:
    """The line (none when it did not run on) saying how the cell ran on after the end."""
    if settle_s <= 0:
        return []
    how = "every part at rest" if at_rest else "the --settle-after limit; not every part at rest"
    return [f"settled: the cell ran on {settle_s:.2f} s after the end ({how})"]


class _Shown(Protocol):
    replay: Optional[str]

    @property
    def ok(self) -> bool: ...

    def summary(self) -> str: ...

    def to_dict(self) -> dict[str, Any]: ...


def show_report(report: _Shown, json_path: Optional[str], out: Callable[[str], None]) -> int:
    """Prints a run's report (``ros-run``'s or ``flexbe-run``'s), writes it as JSON to
    ``json_path`` (when given) and names the replay; the command's exit code."""
    out(report.summary())
    if json_path:
        Path(json_path).write_text(json.dumps(report.to_dict(), indent=2))
        out(f"result: {json_path}")
    if report.replay:
        out(f"replay: {report.replay} (open it in any browser)")
    return 0 if report.ok else 1
