"""Parts: the pre-allocated pool, the spawner, the deletion wall's disposal and the ledger.

Drake cannot add bodies to a built plant, so every part that may ever appear
is in the plant from the start: a pool of ``object_1 ... object_N``. A part in
the pool is *parked*: far from the cell (a row at x = 50 m) with its floating
joint locked (no motion, no contact, no cost in the contact solver). Spawning unlocks the next
parked part and puts it at the spawn pose; disposal parks it again. Parts are
spawned in name order; a disposed part goes to the back of the queue and keeps
its name when it is spawned again.

The bookkeeping (which part is where, what happened when) is a value in the
Context of a :class:`PartManager` system, so it is cloned, reset and
serialized with the rest of the simulation state. World edits (lock, move)
are made by the runtime between advances.
"""

# No `from __future__ import annotations`: SpawnerConfig is a YAML schema.

import math
from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.framework import Context, LeafSystem

from omtp_drake.errors import ConfigError, SimulationError

#: Where parked part k waits (x = PARK_X0 + k * PARK_DX, on a line far from the cell).
PARK_X0, PARK_DX, PARK_Y, PARK_Z = 50.0, 0.5, 50.0, 1.0

def parking_pose(slot: int) -> RigidTransform:
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
            if getattr(self, key) < 0:
                raise ConfigError(f"spawner.{key} must be >= 0, got {getattr(self, key)}")
        if self.max_parts < 0:
            raise ConfigError(f"spawner.max_parts must be >= 0, got {self.max_parts}")


@dataclass(frozen=True)
class PartRecord:
    """One part of the pool."""

    name: str
    #: ``parked`` (in the pool) or ``in_world`` (spawned, not yet disposed).
    state: str = "parked"
    spawned_at: float = math.nan


@dataclass(frozen=True)
class PartBook:
    """The value the PartManager keeps in its Context."""

    parts: tuple[PartRecord, ...]
    #: Pool order in which parked parts are spawned next (indices into ``parts``).
    queue: tuple[int, ...]
    spawn_count: int = 0
    auto_spawns: int = 0
    dispose_count: int = 0
    next_auto_spawn: float = math.inf
    #: (time, event, part) history: "spawn", "dispose".
    events: tuple[tuple[float, str, str], ...] = ()


@dataclass(frozen=True)
class Ledger:
    """Where every spawned part is. Invariant: spawned = sum of the other counts."""

    time: float
    spawned: int
    parked: int
    on_belt: int
    on_floor: int
    held: dict[str, int]
    in_bin: dict[str, int]
    disposed: int
    parts: dict[str, str]

    @property
    def balanced(self) -> bool:
        return self.spawned == (self.on_belt + self.on_floor + sum(self.held.values())
                                + sum(self.in_bin.values()) + self.disposed)

    def to_dict(self) -> dict:
        return {"time": self.time, "spawned": self.spawned, "parked": self.parked,
                "on_belt": self.on_belt, "on_floor": self.on_floor, "held": dict(self.held),
                "in_bin": dict(self.in_bin), "disposed": self.disposed, "parts": dict(self.parts)}


class PartManager(LeafSystem):
    """Holds the :class:`PartBook` of the pool in its Context (no ports, no events).

    The runtime reads and replaces the book between advances; keeping it in the
    Context makes it part of the simulation state.
    """

    def __init__(self, names: list[str], spawner: Optional[SpawnerConfig]):
        super().__init__()
        first = math.inf
        if spawner is not None and spawner.period > 0:
            first = spawner.start_time
        book = PartBook(parts=tuple(PartRecord(n) for n in names),
                        queue=tuple(range(len(names))), next_auto_spawn=first)
        self._index = self.DeclareAbstractState(AbstractValue.Make(book))
        self.spawner = spawner
        self.names = tuple(names)

    def book(self, context: Context) -> PartBook:
        return context.get_abstract_state(self._index).get_value()

    def set_book(self, context: Context, book: PartBook) -> None:
        context.get_mutable_abstract_state(self._index).set_value(book)


def spawn_pose(spawner: SpawnerConfig, seed: int, index: int,
               xyz: Optional[list[float]] = None, yaw: Optional[float] = None) -> RigidTransform:
    """The pose of the ``index``-th spawn: the configured pose plus seeded variance.

    The draw depends only on (seed, index), so runs are reproducible.
    """
    rng = np.random.default_rng((seed, 7919, index))
    dx, dyaw = rng.uniform(-1.0, 1.0, 2)
    p = np.array(xyz if xyz is not None else spawner.xyz, dtype=float)
    if xyz is None:
        p[0] += dx * spawner.lateral_variance
    angle = (yaw if yaw is not None else spawner.yaw) + (
        dyaw * spawner.yaw_variance if yaw is None else 0.0)
    return RigidTransform(RollPitchYaw(0.0, 0.0, angle), p)


def take_from_pool(book: PartBook, time: float) -> tuple[PartBook, int]:
    """Marks the next parked part as spawned; returns the new book and its index."""
    if not book.queue:
        raise SimulationError(
            f"no parked part left in the pool ({len(book.parts)} parts, all in the world); "
            "raise the scenario's part_pool or dispose of parts first")
    index, queue = book.queue[0], book.queue[1:]
    parts = list(book.parts)
    parts[index] = replace(parts[index], state="in_world", spawned_at=time)
    book = replace(book, parts=tuple(parts), queue=queue, spawn_count=book.spawn_count + 1,
                   events=book.events + ((time, "spawn", parts[index].name),))
    return book, index


def return_to_pool(book: PartBook, index: int, time: float) -> PartBook:
    """Marks part ``index`` disposed and queues it to be spawned again later."""
    parts = list(book.parts)
    parts[index] = replace(parts[index], state="parked")
    return replace(book, parts=tuple(parts), queue=book.queue + (index,),
                   dispose_count=book.dispose_count + 1,
                   events=book.events + ((time, "dispose", parts[index].name),))
