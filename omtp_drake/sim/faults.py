"""Applying a scenario's ``faults:`` while the cell runs, and reporting what each did.

:class:`FaultInjector` watches its triggers every :data:`FAULT_CHECK_PERIOD` of
simulated time (between advances, like the driver's world edits), strikes through
the runtime's fault services (``fail_vacuum``, ``black_out_camera``, ``block_arm``,
``knock_part``, ``move_bin``, the belt's power) and keeps one :class:`FaultReport`
per fault that struck: what, when, and the effect (the part that dropped and where
it came to rest, the part knocked, the parts carried with a bin ...).
:class:`~omtp_drake.sim.runtime.FactoryRuntime` installs one when its scenario has
faults, so ``omtp-drake run``, ``Cell`` and ``batch`` all apply them.

Everything depends only on simulated time and the run's state, so a run with
faults is as repeatable as one without.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Optional, Protocol

from pydrake.math import RigidTransform
from pydrake.systems.framework import Context

from omtp_drake.cell.station import Station
from omtp_drake.scenario.faults import FaultConfig
from omtp_drake.sim.ledger import Ledger, held_parts

_log = logging.getLogger(__name__)

#: How often triggers are looked at (s): a fault strikes within 10 ms of its trigger.
FAULT_CHECK_PERIOD = 0.01
#: Times closer than this (s) are the same time.
_EPS = 1e-9
#: A dropped part's resting place is read this long (s) after the drop.
LANDING_TIME = 1.5


class FaultServices(Protocol):
    """What a fault needs of the running cell (:class:`~omtp_drake.sim.runtime.FactoryRuntime` has it)."""

    station: Station
    context: Context

    @property
    def time(self) -> float: ...
    def fail_vacuum(self, robot: str, duration: float) -> None: ...
    def black_out_camera(self, camera: str, duration: float) -> None: ...
    def block_arm(self, robot: str, duration: float) -> None: ...
    def knock_part(self, name: str, velocity: Sequence[float]) -> None: ...
    def move_bin(self, name: str, xyz: Sequence[float], yaw: float = 0.0) -> None: ...
    def set_conveyor_power(self, power: float) -> None: ...
    def conveyor_power(self) -> float: ...
    def break_beam(self) -> tuple[bool, float]: ...
    def ledger(self) -> Ledger: ...
    def part_pose(self, name: str) -> RigidTransform: ...
    def parts_in_world(self) -> list[str]: ...


@dataclass
class FaultReport:
    """One fault that struck: ``effect`` says what it did (JSON-ready)."""

    name: str
    kind: str
    target: str
    time: float
    until: Optional[float] = None
    effect: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "kind": self.kind,
            "target": self.target,
            "time": round(self.time, 6),
            "until": None if self.until is None else round(self.until, 6),
            "effect": self.effect,
        }


def fault_line(fault: dict[str, Any]) -> str:
    """One line of what a fault did (``fault`` as :meth:`FaultReport.to_dict` gives it):
    ``drop (vacuum_failure robot2) at 3.95-4.45 s: dropped object_1, landed on_floor at
    (-8.460, -1.755, 0.101)``."""
    span = f"{fault['time']:.2f}" + (f"-{fault['until']:.2f}" if fault["until"] is not None else "")
    head = f"{fault['name']} ({fault['kind']}{' ' + fault['target'] if fault['target'] else ''}) at {span} s"
    effect = fault["effect"]
    words = []
    if "dropped" in effect:
        words.append(f"dropped {effect['dropped']}" if effect["dropped"] else "held nothing")
    if "landed" in effect:
        x, y, z = effect["landed"]["position"]
        words.append(f"landed {effect['landed']['where']} at ({x:.3f}, {y:.3f}, {z:.3f})")
    if "knocked" in effect:
        words.append(
            f"knocked {effect['knocked']}" if effect["knocked"] else f"knocked nothing: {effect['why']}"
        )
    if "carried" in effect:
        words.append(f"carried {', '.join(effect['carried']) or 'no part'}")
    return head + (": " + ", ".join(words) if words else "")


@dataclass
class _Watch:
    """The state of one fault's trigger between checks."""

    fault: FaultConfig
    seen: int = 0  # events counted so far
    since: Optional[float] = None  # when the counted event happened (holding: the hold began)
    active: bool = False  # the event's condition held at the last check
    done: bool = False


class FaultInjector:
    """Strikes each fault of ``faults`` when its trigger fires (see the module doc).

    Call it every :data:`FAULT_CHECK_PERIOD` (``FactoryRuntime`` does).
    """

    def __init__(self, runtime: FaultServices, faults: list[FaultConfig]):
        self._rt = runtime
        self._watches = [_Watch(f) for f in faults]
        self._landings: list[tuple[float, FaultReport, str]] = []
        self._belt_holds: list[tuple[float, float]] = []  # (until, power to restore)
        self.reports: list[FaultReport] = []

    @property
    def period(self) -> float:
        return FAULT_CHECK_PERIOD

    def __call__(self) -> None:
        rt = self._rt
        t = rt.time
        waiting = [w for w in self._watches if not w.done]
        if waiting:  # the cell is read only while a fault still waits for its trigger
            held = held_parts(rt.station, rt.context)
            watch_beam = any(w.fault.event == "beam" for w in waiting)
            beam = bool(rt.break_beam()[0]) if watch_beam else False
            for watch in waiting:
                if self._due(watch, t, held, beam):
                    watch.done = True
                    self.reports.append(self._strike(watch.fault, t, held))
        if self._belt_holds:
            self._hold_belts(t)
        if self._landings:
            self._read_landings(t)

    def _due(self, watch: _Watch, t: float, held: dict[str, str], beam: bool) -> bool:
        """Has ``watch``'s trigger fired? ``holding``: a hold (the n-th or a later
        one) has lasted ``after``; ``attach`` / ``beam``: ``after`` has passed since
        the n-th attach / beam break."""
        fault = watch.fault
        if fault.at is not None:
            return t >= fault.at - _EPS
        on = beam if fault.event == "beam" else fault.robot in held
        if on and not watch.active:  # the event happens (a rising edge)
            watch.seen += 1
            if watch.seen >= fault.count and (watch.since is None or fault.event == "holding"):
                watch.since = t
        if fault.event == "holding" and not on:
            watch.since = None  # the hold ended before it lasted `after`
        watch.active = on
        return watch.since is not None and t >= watch.since + fault.after - _EPS

    def _strike(self, fault: FaultConfig, t: float, held: dict[str, str]) -> FaultReport:
        rt = self._rt
        report = FaultReport(fault.name, fault.kind, fault.target(), t)
        if fault.kind == "vacuum_failure":
            rt.fail_vacuum(fault.robot, fault.duration)
            report.until = t + fault.duration
            part = held.get(fault.robot)
            report.effect = {"dropped": part}
            if part:
                self._landings.append((t + LANDING_TIME, report, part))
        elif fault.kind == "camera_blackout":
            rt.black_out_camera(fault.camera, fault.duration)
            report.until = t + fault.duration
        elif fault.kind == "arm_blocked":
            rt.block_arm(fault.robot, fault.duration)
            report.until = t + fault.duration
        elif fault.kind == "belt_stop":
            self._belt_holds.append((t + fault.duration, rt.conveyor_power()))
            rt.set_conveyor_power(0.0)
            report.until = t + fault.duration
        elif fault.kind == "part_knocked":
            report.effect = self._knock(fault)
        elif fault.kind == "bin_moved":
            carried = [n for n, where in rt.ledger().parts.items() if where == f"in_bin:{fault.bin}"]
            rt.move_bin(fault.bin, fault.xyz, fault.yaw)
            report.effect = {"xyz": list(fault.xyz), "yaw": fault.yaw, "carried": carried}
        _log.info("t=%.3f fault %s (%s) strikes %s", t, fault.name, fault.kind, report.target or "-")
        return report

    def _knock(self, fault: FaultConfig) -> dict[str, Any]:
        rt = self._rt
        resting = [n for n, where in rt.ledger().parts.items() if where in ("on_floor", "on_belt")]
        part = fault.part or (resting[-1] if resting else "")
        if not part or part not in rt.parts_in_world():
            return {
                "knocked": None,
                "why": "no part resting in the world" if not part else f"{part} not in the world",
            }
        rt.knock_part(part, fault.velocity)
        return {"knocked": part, "velocity": list(fault.velocity)}

    def _hold_belts(self, t: float) -> None:
        """A stopped belt stays stopped (whatever restarts it) until its fault ends."""
        rt = self._rt
        still = []
        for until, power in self._belt_holds:
            if t < until - _EPS:
                rt.set_conveyor_power(0.0)
                still.append((until, power))
            else:
                rt.set_conveyor_power(power)
        self._belt_holds = still

    def _read_landings(self, t: float) -> None:
        rt = self._rt
        due = [x for x in self._landings if t >= x[0] - _EPS]
        self._landings = [x for x in self._landings if t < x[0] - _EPS]
        for _, report, part in due:
            p = rt.part_pose(part).translation()
            report.effect["landed"] = {
                "where": rt.ledger().parts.get(part, "disposed"),
                "position": [round(float(x), 4) for x in p],
            }
