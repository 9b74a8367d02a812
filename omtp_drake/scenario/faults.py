"""Faults as data: what goes wrong in a run, when, and for how long (ARIAC's trials style).

A scenario's ``faults:`` list declares them; :mod:`omtp_drake.sim.faults` applies
them while the cell runs (``omtp-drake run``, ``Cell``, ``batch``, where ``--set
faults.<name>.at=...`` sweeps a fault's time) and reports each one in the result::

    faults:
      - {name: drop, kind: vacuum_failure, robot: robot2, event: holding, after: 1.85, duration: 0.5}
      - {name: dark, kind: camera_blackout, camera: logical_camera_2, at: 4.0, duration: 1.0}
      - {name: jam, kind: belt_stop, at: 6.0, duration: 2.0}
      - {name: stuck, kind: arm_blocked, robot: robot1, event: attach, count: 2, duration: 1.0}
      - {name: bump, kind: part_knocked, at: 3.0, velocity: [0.8, 0.0, 0.0]}
      - {name: shove, kind: bin_moved, bin: bin_1, event: beam, xyz: [-8.0, -2.5, 0.0]}

The trigger is either ``at`` (simulated seconds) or an ``event`` with ``count``
(the n-th time it happens) and ``after`` (seconds later):

- ``holding``: ``robot`` has held a part for ``after`` s (the n-th hold);
- ``attach``: ``robot``'s gripper attached a part (the n-th attach);
- ``beam``: a part broke the break beam (the n-th time it went from clear to broken).
"""

# No `from __future__ import annotations`: Drake's typed YAML loader reads the field types.
import math
from dataclasses import dataclass, field
from typing import Optional

from omtp_drake.errors import ConfigError, UnknownNameError

#: What can go wrong, and the target field each kind needs.
FAULT_TARGETS = {
    "vacuum_failure": "robot",
    "camera_blackout": "camera",
    "belt_stop": "",
    "arm_blocked": "robot",
    "part_knocked": "part",
    "bin_moved": "bin",
}
FAULT_KINDS = tuple(FAULT_TARGETS)
#: Events a fault may wait for (see the module doc).
FAULT_EVENTS = ("holding", "attach", "beam")
#: Kinds that last ``duration`` seconds (the others are one push).
LASTING = ("vacuum_failure", "camera_blackout", "belt_stop", "arm_blocked")
#: The fastest knock (m/s), as FactoryRuntime.knock_part allows.
MAX_KNOCK_SPEED = 20.0


@dataclass
class FaultConfig:
    """One fault of a scenario's ``faults:`` list (see the module doc)."""

    #: Names the fault in reports and in ``--set faults.<name>.at=...``.
    name: str = "fault"
    kind: str = "vacuum_failure"
    #: The target: ``robot`` (vacuum_failure, arm_blocked; also whose hold or
    #: attach an event counts), ``camera`` (camera_blackout), ``part``
    #: (part_knocked; empty: the part that came to rest last), ``bin`` (bin_moved).
    robot: str = ""
    camera: str = ""
    part: str = ""
    bin: str = ""
    #: Trigger: a simulated time, or an event (with ``count`` and ``after``).
    at: Optional[float] = None
    event: str = ""
    count: int = 1
    after: float = 0.0
    #: How long a lasting fault lasts (s).
    duration: float = 0.0
    #: part_knocked: the velocity (m/s, world) the part is knocked to.
    velocity: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: bin_moved: where the bin's base goes (world) and its yaw.
    xyz: list[float] = field(default_factory=list)
    yaw: float = 0.0

    def validate(self) -> None:
        """Raises :class:`ConfigError` (or :class:`UnknownNameError`) naming the
        fault, the key and the valid values; references to robots, cameras and
        bins are checked by the Scenario, which knows them."""
        where = f"faults[{self.name}]"
        if self.kind not in FAULT_TARGETS:
            raise UnknownNameError(f"{where}.kind", self.kind, FAULT_KINDS)
        target = FAULT_TARGETS[self.kind]
        if target and target != "part" and not getattr(self, target):
            raise ConfigError(f"{where}: kind {self.kind} needs {target}: the {target} it strikes")
        if (self.at is None) == (not self.event):
            raise ConfigError(
                f"{where}: give exactly one trigger, at: <simulated s> or event: "
                f"{' | '.join(FAULT_EVENTS)}; got at={self.at!r}, event={self.event!r}"
            )
        if self.at is not None and not (self.at >= 0 and math.isfinite(self.at)):
            raise ConfigError(f"{where}.at must be a time >= 0 s, got {self.at!r}")
        if self.event:
            if self.event not in FAULT_EVENTS:
                raise UnknownNameError(f"{where}.event", self.event, FAULT_EVENTS)
            if self.event in ("holding", "attach") and not self.robot:
                raise ConfigError(f"{where}: event {self.event} needs robot: whose gripper it watches")
        if isinstance(self.count, bool) or not isinstance(self.count, int) or self.count < 1:
            raise ConfigError(f"{where}.count must be an integer >= 1, got {self.count!r}")
        if not (self.after >= 0 and math.isfinite(self.after)):
            raise ConfigError(f"{where}.after must be a time >= 0 s, got {self.after!r}")
        if self.kind in LASTING and not (self.duration > 0 and math.isfinite(self.duration)):
            raise ConfigError(f"{where}.duration must be a time > 0 s for {self.kind}, got {self.duration!r}")
        if self.kind == "part_knocked":
            speed = math.sqrt(sum(v * v for v in self.velocity)) if len(self.velocity) == 3 else math.nan
            if not 0 < speed <= MAX_KNOCK_SPEED:
                raise ConfigError(
                    f"{where}.velocity must be 3 numbers of speed in (0, {MAX_KNOCK_SPEED:g}] m/s, "
                    + (f"got {self.velocity!r}" if any(self.velocity) else "required for part_knocked")
                )
        if self.kind == "bin_moved" and (len(self.xyz) != 3 or not math.isfinite(self.yaw)):
            raise ConfigError(f"{where}.xyz must be 3 numbers (the bin's new base), got {self.xyz!r}")

    def target(self) -> str:
        """The name of what the fault strikes ("" for the belt or a knock of the last part)."""
        field_name = FAULT_TARGETS[self.kind]
        return getattr(self, field_name) if field_name else ""
