"""Parts: the pre-allocated pool, the spawner's settings and spawn poses.

Drake cannot add bodies to a built plant, so every part that may ever appear
is in the plant from the start: the scenario's placed parts and a pool of
``object_1 ... object_N``. A part out of the world is *parked*: far from the
cell (a row at x = 50 m) with its floating joint locked (no motion, no contact,
no cost in the contact solver). Spawning unlocks the next parked pool part and
puts it at the spawn pose; disposal parks a part again. Pool parts are spawned
in name order; a disposed pool part goes to the back of the queue and keeps its
name when it is spawned again (a disposed placed part stays parked).

Whether a part is parked is the lock of its joint in the plant's Context, so
it is never restated elsewhere. :class:`PartPool` makes the world edits (lock,
move) between advances and logs what it did; the driver owns it.
"""

# No `from __future__ import annotations`: SpawnerConfig is a YAML schema.

import logging
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.framework import Context

from omtp_drake.errors import MAX_RATE_HZ, ConfigError, SimulationError, UnknownNameError

if TYPE_CHECKING:
    from omtp_drake.station import Station

_log = logging.getLogger(__name__)

#: Where parked part k waits (x = PARK_X0 + k * PARK_DX, on a line far from the cell).
PARK_X0, PARK_DX, PARK_Y, PARK_Z = 50.0, 0.5, 50.0, 1.0


def parking_pose(slot: int) -> RigidTransform:
    """``X_WP`` of the part parked in ``slot`` (its index among all parts)."""
    return RigidTransform([PARK_X0 + slot * PARK_DX, PARK_Y, PARK_Z])


@dataclass
class SpawnerConfig:
    """Where and when parts appear (the course's spawner and ``spawn_object_once``)."""

    #: Spawn position (world) of the part's centre.
    xyz: list[float] = field(default_factory=lambda: [1.2, 2.5, 1.021])
    #: Spawn yaw (rad) about world z.
    yaw: float = 0.0
    #: Uniform random offset in [-v, v] along world x (across the belt) and in yaw.
    lateral_variance: float = 0.0
    yaw_variance: float = 0.0
    #: Seconds between automatic spawns; 0 = only on request.
    period: float = 0.0
    #: Time of the first automatic spawn.
    start_time: float = 0.0
    #: Spawn only when no other spawned part is in the world (``spawn_object_once``).
    one_at_a_time: bool = True
    #: Stop after this many automatic spawns; 0 = no limit.
    max_parts: int = 0

    def validate(self) -> None:
        if len(self.xyz) != 3:
            raise ConfigError(f"spawner.xyz needs 3 numbers, got {list(self.xyz)}")
        for key in ("lateral_variance", "yaw_variance", "period", "start_time"):
            value = getattr(self, key)
            if not (value >= 0 and math.isfinite(value)):
                raise ConfigError(f"spawner.{key} must be a finite number >= 0, got {value}")
        if 0 < self.period < 1.0 / MAX_RATE_HZ:
            raise ConfigError(
                f"spawner.period must be 0 (no automatic spawns) or >= {1.0 / MAX_RATE_HZ:g} s, "
                f"got {self.period}"
            )
        if self.max_parts < 0:
            raise ConfigError(f"spawner.max_parts must be >= 0, got {self.max_parts}")


def spawn_pose(
    spawner: SpawnerConfig,
    seed: int,
    index: int,
    xyz: Optional[list[float]] = None,
    yaw: Optional[float] = None,
) -> RigidTransform:
    """The pose of the ``index``-th spawn: the configured pose plus seeded variance,
    or ``xyz`` / ``yaw`` as given (no variance on what is given).

    The draw depends only on (seed, index), so runs are reproducible.
    """
    rng = np.random.default_rng((seed, 7919, index))
    dx, dyaw = rng.uniform(-1.0, 1.0, 2)
    p = np.array(xyz if xyz is not None else spawner.xyz, dtype=float)
    if xyz is None:
        p[0] += dx * spawner.lateral_variance
    angle = (yaw if yaw is not None else spawner.yaw) + (dyaw * spawner.yaw_variance if yaw is None else 0.0)
    return RigidTransform(RollPitchYaw(0.0, 0.0, angle), p)


@dataclass(frozen=True)
class PartEvent:
    """One thing that happened to a part: ``spawn`` or ``dispose``."""

    time: float
    event: str
    part: str


class PartPool:
    """Spawns, parks and disposes of the station's parts, between advances.

    Every part of the station (placed and pool) has a parking slot; the pool's
    parts start parked (:meth:`Station.initialize_context`). The log of spawns and
    disposals (:attr:`events`) is a record of what happened, for the ledger and
    reports; the state of each part is its joint's lock in the Context.
    """

    def __init__(self, station: "Station"):
        self._station = station
        plant = station.plant
        self._names = list(station.parts)
        self._pool = list(station.pool)
        self._joints = {}
        for name in self._names:
            (index,) = plant.GetJointIndices(station.parts[name])
            self._joints[name] = plant.get_joint(index)
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
        return [n for n in self._names if not self._joints[n].is_locked(plant_context)]

    def queue(self, root_context: Context) -> list[str]:
        """The parked pool parts in the order they will be spawned: never spawned
        ones in name order, then the disposed ones in the order they were disposed."""
        plant_context = self._plant_context(root_context)
        parked = [n for n in self._pool if self._joints[n].is_locked(plant_context)]
        disposed_at = {e.part: e.time for e in self.events if e.event == "dispose"}
        return sorted(parked, key=lambda n: (disposed_at.get(n, -math.inf), self._pool.index(n)))

    def spawn(self, root_context: Context, X_WP: RigidTransform) -> str:
        """Puts the next parked pool part at ``X_WP``, at rest; returns its name."""
        queue = self.queue(root_context)
        if not queue:
            raise SimulationError(
                f"no parked part left in the pool ({len(self._pool)} parts, all in the world); "
                "raise the scenario's part_pool or dispose of parts first"
            )
        name = queue[0]
        self._station.unpark(self._plant_context(root_context), name, X_WP)
        self.events.append(PartEvent(root_context.get_time(), "spawn", name))
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
        self._station.park(self._plant_context(root_context), name)
        self.written_off.discard(name)
        self.events.append(PartEvent(root_context.get_time(), "dispose", name))
        _log.info("t=%.2f disposed of %s", root_context.get_time(), name)

    def _plant_context(self, root_context: Context) -> Context:
        return self._station.plant.GetMyMutableContextFromRoot(root_context)
