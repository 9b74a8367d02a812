"""The part pool while the cell runs: which parts are parked, spawning and disposal.

Whether a part is parked is in the plant's Context (its joint locked at its
parking slot, :class:`omtp_drake.cell.parts.PartStates`), so it is never restated elsewhere.
:class:`PartPool` makes the world edits (lock, move) between advances and logs
what it did; the driver owns it. Poses of parked and spawned parts are in
:mod:`omtp_drake.cell.parts`.
"""

import logging
import math
from dataclasses import dataclass
from typing import Optional

from pydrake.math import RigidTransform
from pydrake.systems.framework import Context

from omtp_drake.cell.station import Station
from omtp_drake.errors import SimulationError, UnknownNameError

_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class PartEvent:
    """One thing that happened to a part: ``spawn`` or ``dispose``."""

    time: float
    event: str
    part: str
    #: Where a spawned part entered the world (``X_WP``; None for a disposal).
    pose: Optional[RigidTransform] = None


class PartPool:
    """Spawns, parks and disposes of the station's parts, between advances.

    Every part of the station (placed and pool) has a parking slot; the pool's
    parts start parked (:meth:`Station.initialize_context`). The log of spawns and
    disposals (:attr:`events`) is a record of what happened, for the ledger and
    reports; whether each part is parked is in the Context (``station.part_states``).
    """

    def __init__(self, station: "Station"):
        self._station = station
        self._names = list(station.parts)
        self._pool = list(station.pool)
        self.events: list[PartEvent] = []
        #: Parts given up on (lost where nobody can pick them): they stay where they
        #: are, in the ledger, but no longer hold the spawner back.
        self.written_off: set[str] = set()

    @property
    def names(self) -> list[str]:
        """Every part: the placed ones, then the pool."""
        return list(self._names)

    @property
    def spawn_count(self) -> int:
        return sum(e.event == "spawn" for e in self.events)

    @property
    def dispose_count(self) -> int:
        return sum(e.event == "dispose" for e in self.events)

    def in_world(self, root_context: Context) -> list[str]:
        """The parts in the world (placed and spawned, not disposed of), in name order."""
        plant_context = self._plant_context(root_context)
        parked = set(self._station.part_states.parked(plant_context))
        return [n for n in self._names if n not in parked]

    def queue(self, root_context: Context) -> list[str]:
        """The parked pool parts in the order they will be spawned: never spawned
        ones in name order, then the disposed ones in the order they were disposed."""
        plant_context = self._plant_context(root_context)
        parked_now = set(self._station.part_states.parked(plant_context))
        parked = [n for n in self._pool if n in parked_now]
        disposed_at = {e.part: e.time for e in self.events if e.event == "dispose"}
        return sorted(parked, key=lambda n: (disposed_at.get(n, -math.inf), self._pool.index(n)))

    def spawn(self, root_context: Context, X_WP: RigidTransform, kind: Optional[str] = None) -> str:
        """Puts the next parked pool part (of object ``kind`` when given: the
        station's ``pool_kinds``) at ``X_WP``, at rest; returns its name."""
        queue = self.queue(root_context)
        if kind is not None:
            queue = [n for n in queue if self._station.pool_kinds.get(n) == kind]
        if not queue:
            of = f" of object {kind!r}" if kind is not None else ""
            raise SimulationError(
                f"no parked part{of} left in the pool ({len(self._pool)} parts, all in the world); "
                "raise the scenario's part_pool or dispose of parts first"
            )
        name = queue[0]
        self._station.part_states.unpark(root_context, name, X_WP)
        self.events.append(PartEvent(root_context.get_time(), "spawn", name, X_WP))
        _log.info("t=%.2f spawned %s at %s", root_context.get_time(), name, X_WP.translation())
        return name

    def check_in_world(self, root_context: Context, name: str) -> None:
        """UnknownNameError (listing the parts in the world) unless ``name`` is one."""
        in_world = self.in_world(root_context)
        if name not in in_world:
            raise UnknownNameError("part in the world", name, in_world)

    def write_off(self, root_context: Context, name: str) -> None:
        """Gives up on part ``name``: it stays in the world, but no longer holds a
        one-at-a-time spawner back."""
        self.check_in_world(root_context, name)
        self.written_off.add(name)

    def dispose(self, root_context: Context, name: str) -> None:
        """Takes part ``name`` out of the world (parks it)."""
        self.check_in_world(root_context, name)
        self._station.part_states.park(root_context, name)
        self.written_off.discard(name)
        self.events.append(PartEvent(root_context.get_time(), "dispose", name))
        _log.info("t=%.2f disposed of %s", root_context.get_time(), name)

    def _plant_context(self, root_context: Context) -> Context:
        return self._station.plant.GetMyMutableContextFromRoot(root_context)
