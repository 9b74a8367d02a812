"""After a script or behaviour ends, the world runs on until its parts rest (``--settle-after``).

In the course's Gazebo cell the world does not stop with the script: a part the
script let go of falls and lies where it lands. So the report of a ``ros-run`` or
``flexbe-run`` is taken after the cell has settled: the cell runs on (simulated time)
until every part in the world rests, at most ``--settle-after`` seconds (default
:data:`SETTLE_AFTER`; 0: the report is taken at the end, as before).

A part rests when it has been still for the scenario's ``sleep.rest_time`` (slower than
``sleep.linear_speed`` and ``sleep.angular_speed``, the same rule that lets a part fall
asleep, :mod:`omtp_drake.cell.rest_clock`), counted from the end at the earliest: a part
held at the end may still be let go of. So the world runs on at least ``rest_time``
(0.5 s by default); a part on a running belt never rests, so then it runs the whole
``--settle-after``. A scenario whose parts never sleep (``sleep.enabled: false``, or a cell
without parts, such as a robot alone in Gazebo's empty world) has no rest clock: the
world runs the whole ``--settle-after`` unless it holds no part at all.

Meanwhile the script's node is gone: no callbacks run, and no new parts come (the
spawner is stopped, as by ``/stop_spawn``): the report counts the parts the run made.
While Gazebo's physics is paused the world stands still and nothing settles.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session

#: How long (simulated s) the world runs on at most after a run, by default.
SETTLE_AFTER = 3.0
_EPS = 1e-9


@dataclass(frozen=True)
class Settled:
    """How the world ran on after a run: when the run ended (simulated s), for how long it
    ran on (s), and whether every part rests."""

    end: float
    seconds: float
    at_rest: bool


def check_settle_after(seconds: float) -> float:
    """``seconds`` as finite seconds >= 0, or one ConfigError naming ``--settle-after``."""
    try:
        value = float(seconds)
    except (TypeError, ValueError):
        raise ConfigError(f"--settle-after must be simulated seconds >= 0, got {seconds!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise ConfigError(f"--settle-after must be finite simulated seconds >= 0 (0: none), got {seconds!r}")
    return value


def run_on(session: Session, seconds: float) -> Settled:
    """Runs ``session``'s cell on for up to ``seconds`` until its parts rest (module doc)."""
    cell = session.cell
    start = cell.time
    if seconds <= 0 or session.gazebo.clock_stopped() is not None:
        return Settled(start, 0.0, False)
    _stop_spawning(session)
    limit = start + seconds
    rests = _rest_test(session, start)
    while cell.time < limit - _EPS:
        cell.runtime.advance_to(min(limit, cell.time + session.tick))
        if rests():
            return Settled(start, cell.time - start, True)
    return Settled(start, cell.time - start, rests())


def finish(session: Session, seconds: float) -> tuple[Settled, Optional[Path]]:
    """A run's last step: the cell runs on (:func:`run_on`), then is closed, even when that
    fails; how it ran on, and the replay file (None without ``--record``)."""
    try:
        settled = run_on(session, seconds)
    finally:
        session.close_taps()  # --bag: finished with the run's last message
        replay = session.cell.close()
    return settled, replay


def _stop_spawning(session: Session) -> None:
    cell = session.cell
    cell.runtime.auto_spawn = False
    stop = session.services.get("/stop_spawn")
    if stop is not None:
        stop.handler(stop.type._request_class())


def _rest_test(session: Session, start: float) -> Callable[[], bool]:
    """A test of whether every part in the world rests now (without a rest clock: whether
    there is no part in the world)."""
    cell = session.cell
    clock = cell.station.rest_clock
    if clock is None:  # parts never sleep: only a world without parts is known to rest
        return lambda: not cell.runtime.parts_in_world()
    rest_time = cell.scenario.sleep.rest_time
    names = clock.part_names

    def rests() -> bool:
        t = cell.time
        if t < start + rest_time - _EPS:
            return False
        since = dict(zip(names, clock.still_since_values(clock.GetMyContextFromRoot(cell.runtime.context))))
        return all(since[p] <= t - rest_time + _EPS for p in cell.runtime.parts_in_world())

    return rests
