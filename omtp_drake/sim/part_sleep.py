"""Parts at rest fall asleep and wake when touched: a world edit of the driver.

A sleeping part has its joint locked (the contact solver drops it) where it lies;
see :mod:`omtp_drake.cell.rest_clock` and the scenario's :class:`SleepConfig`. At each
check (``sleep.check_rate_hz``), :class:`PartSleep`:

1. wakes every sleeping part that something that may move touches (an arm, a
   cup, the belt, a held part, a part that moved at the latest sample of the
   :class:`~omtp_drake.cell.rest_clock.RestClock`) or that a gripper holds;
2. puts to sleep every awake part that has been still for ``sleep.rest_time``,
   that no gripper holds, and that lies on something (the floor, a bin, a
   still part) and touches nothing that may move.

Touching is geometric (SceneGraph's penetration query between collision
geometries), as for the deletion wall. Between checks a sleeping part is as
fixed as the floor: a part dropped onto it rests on it until the next check
wakes it (at most one check period, 100 ms by default).

The rest clock's samples are :class:`PartSleep`'s too (right before the advance
from each check time, where the clock's own periodic event would run), taken only
while some part is free: while every part is locked (parked or asleep) nothing can
come to rest, and the clock records that once instead.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError
from omtp_drake.sim.ledger import held_parts

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

#: Times closer than this (s) are the same time.
_EPS = 1e-9


class PartSleep:
    """The world edit that puts resting parts to sleep and wakes them, and samples the
    rest clock (module doc; an :class:`~omtp_drake.sim.driver.EventSource` with no
    stops of its own)."""

    def __init__(self, station: Station):
        if station.rest_clock is None:
            raise ConfigError(
                "parts sleep only in a station built with sleep.enabled: true (it has no rest clock)"
            )
        self._station = station
        self._clock = station.rest_clock
        config = station.scenario.sleep
        self.period = 1.0 / config.check_rate_hz
        self._rest_time = config.rest_time
        self._names = self._clock.part_names
        geometries = station.part_states.geometries
        #: collision geometry (its id's value) -> its part's name, or "" (a body welded to
        #: the world); any other (arms, cups, the belt, all of which may move) is absent:
        #: None. Keyed by int: hashing an int costs less than hashing a GeometryId.
        self._owner: dict[int, str] = {g.get_value(): "" for g in geometries.anchored}
        for name, ids in geometries.parts.items():
            self._owner.update((g.get_value(), name) for g in ids)

    def next_time(self, root_context: Context) -> float:
        """No stops besides the checks (the clock samples at the check times)."""
        return math.inf

    def before_advance(self, root_context: Context) -> None:
        """At a sample time, right before the advance (where the clock's own periodic
        event would run, after every edit made at this time): the clock's sample while a
        part is free, else the record that all are locked."""
        t = root_context.get_time()
        if abs(round(t / self.period) * self.period - t) >= _EPS * max(1.0, abs(t)):
            return  # not a sample time (a stop of another edit, or the caller's)
        clock_context = self._clock.GetMyMutableContextFromRoot(root_context)
        plant_context = self._station.plant.GetMyContextFromRoot(root_context)
        if self._station.part_states.any_free(plant_context):
            self._clock.sample(clock_context)
        else:
            self._clock.all_locked_at(clock_context, t)

    def __call__(self, root_context: Context) -> None:
        t = root_context.get_time()
        clock_context = self._clock.GetMyMutableContextFromRoot(root_context)
        since = self._clock.still_since_values(clock_context).tolist()
        latest = t - self._rest_time + _EPS  # still since then or earlier: at rest
        if not any(v <= latest for v in since):
            return  # every part moved within rest_time (a locked part is still): nothing to do
        station, plant = self._station, self._station.plant
        plant_context = plant.GetMyMutableContextFromRoot(root_context)
        parked, asleep = station.part_states.locked(plant_context)
        out = set(asleep).union(parked)
        resting = [n for n, v in zip(self._names, since) if v <= latest and n not in out]
        if not asleep and not resting:
            return  # nothing may sleep or wake: no query
        held = set(held_parts(station, root_context).values())
        if held:
            resting = [n for n in resting if n not in held]
            if not asleep and not resting:
                return  # only held parts are still: none may sleep
        # What moves: arms, cups, the belt, held parts, and awake parts that moved
        # at the clock's latest sample. Whatever is welded to the world does not.
        moving = held.union(n for n, v in zip(self._names, since) if v == math.inf and n not in out)
        touches = self._touches(plant_context)
        for name in sorted(asleep):
            contacts = touches.get(name, _NOTHING)
            if name in held or None in contacts or not moving.isdisjoint(contacts):
                station.part_states.wake(root_context, name)
                self._clock.restart(clock_context, name, t)
        for name in sorted(resting):
            contacts = touches.get(name, _NOTHING)
            if contacts and None not in contacts and moving.isdisjoint(contacts):
                station.part_states.sleep(root_context, name)

    def _touches(self, plant_context: Context) -> dict[str, set]:
        """part -> the owners of what it touches (SceneGraph's penetration query)."""
        owner = self._owner.get
        touches: dict[str, set] = {}
        query = self._station.plant.get_geometry_query_input_port().Eval(plant_context)
        for pair in query.ComputePointPairPenetration():
            a, b = owner(pair.id_A.get_value()), owner(pair.id_B.get_value())
            if a:
                touches.setdefault(a, set()).add(b)
            if b:
                touches.setdefault(b, set()).add(a)
        return touches


#: No contacts.
_NOTHING: frozenset = frozenset()
