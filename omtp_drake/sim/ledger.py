"""The ledger: where every part that entered the world is, now.

Each part in the world is in exactly one place:

* ``held``: a vacuum gripper holds it (the detail names the robot);
* ``in_bin``: its centre (the middle of its bounding box) is inside a bin's inner
  footprint, above the bin's floor (resting on the floor of the bin or on other parts in it);
* ``on_belt``: over the belt and resting on (or just above) its surface (tilted or not);
* ``on_floor``: resting on (or just above) the cell's floor;
* ``elsewhere``: none of these (e.g. on a pedestal or falling); the detail is
  its position.

Parts that left the world are ``disposed`` (by the deletion wall or
``remove_part``). Invariant: spawned = held + in bins + on belt + on floor +
elsewhere + disposed.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station
    from omtp_drake.sim.pool import PartPool

#: A part whose lowest point is this close (m) above a surface rests on it.
RESTING_GAP = 0.02


@dataclass(frozen=True)
class Ledger:
    """Where every part that entered the world is (see the module doc)."""

    time: float
    spawned: int
    parked: int
    on_belt: int
    on_floor: int
    elsewhere: int
    held: dict[str, int]
    in_bin: dict[str, int]
    disposed: int
    #: part -> ``held:robot2``, ``in_bin:bin_1``, ``on_belt``, ``on_floor`` or
    #: ``elsewhere:(x, y, z)``.
    parts: dict[str, str]

    @property
    def balanced(self) -> bool:
        return self.spawned == (
            self.on_belt
            + self.on_floor
            + self.elsewhere
            + sum(self.held.values())
            + sum(self.in_bin.values())
            + self.disposed
        )

    @property
    def loose(self) -> int:
        """Parts in the world that are neither held nor in a bin."""
        return self.on_belt + self.on_floor + self.elsewhere

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Ledger:
        """The ledger of :meth:`to_dict` (other keys ignored)."""
        return cls(**{f.name: data[f.name] for f in dataclasses.fields(cls)})

    def summary_line(self) -> str:
        return (
            f"ledger: spawned {self.spawned} = in bins {sum(self.in_bin.values())} + held "
            f"{sum(self.held.values())} + on belt {self.on_belt} + on floor {self.on_floor} "
            f"+ elsewhere {self.elsewhere} + disposed {self.disposed}"
        )


def held_parts(station: Station, root_context: Context) -> dict[str, str]:
    """robot -> the part its vacuum gripper holds (robots holding nothing are absent)."""
    held = {}
    for robot, gripper in station.grippers.items():
        state = gripper.get_state(gripper.GetMyContextFromRoot(root_context))
        if state.attached:
            held[robot] = state.part
    return held


def locate(station: Station, root_context: Context, name: str, held: dict[str, str]) -> tuple[str, str]:
    """(place, detail) of part ``name`` in the world (see the module doc)."""
    for robot, part in held.items():
        if part == name:
            return "held", robot
    X_WP = _pose(station, root_context, name)
    centre, half = station.scenario.part_box(name)
    p = X_WP @ centre  # the middle of the part's box (a mesh's origin may be anywhere in it)
    in_bin = _bin_at(station, root_context, p)
    if in_bin is not None:
        return "in_bin", in_bin
    belt = station.belt
    if belt is not None and belt.over(p) and belt.height(p) - _reach(X_WP, half, belt.normal) < RESTING_GAP:
        return "on_belt", ""
    if p[2] - _reach(X_WP, half, np.array([0.0, 0.0, 1.0])) < RESTING_GAP:
        return "on_floor", ""
    return "elsewhere", "({:.3f}, {:.3f}, {:.3f})".format(*p)


def bin_of(station: Station, root_context: Context, name: str) -> Optional[str]:
    """The bin part ``name`` lies in (as :func:`locate` says ``"in_bin"``); None when none.
    What the spawner asks of each part at its checks: the rest of :func:`locate` (the
    belt, the floor) is not needed there."""
    return _bin_at(
        station, root_context, _pose(station, root_context, name) @ station.scenario.part_box(name)[0]
    )


def _pose(station: Station, root_context: Context, name: str) -> RigidTransform:
    """``X_WP``: where part ``name`` is now."""
    plant = station.plant
    plant_context = plant.GetMyContextFromRoot(root_context)
    return plant.EvalBodyPoseInWorld(plant_context, plant.GetBodyByName(name, station.parts[name]))


def _bin_at(station: Station, root_context: Context, p_W: np.ndarray) -> Optional[str]:
    """The first of the scenario's bins that holds the point ``p_W``; None when none."""
    for b in station.scenario.bins:
        if b.contains(p_W, station.bin_pose(root_context, b.name)):
            return b.name
    return None


def _reach(X_WP: RigidTransform, half: np.ndarray, n_W: np.ndarray) -> float:
    """How far the part's box (``half`` extents, in its frame, at pose ``X_WP``) reaches from
    its middle along the world direction ``n_W`` (unit)."""
    return float(np.abs(X_WP.rotation().matrix().T @ n_W) @ half)


def take_ledger(station: Station, root_context: Context, pool: PartPool) -> Ledger:
    """The ledger of the station's parts in ``root_context``."""
    held_by = held_parts(station, root_context)
    held = {r: 0 for r in station.arms}
    in_bin = {b.name: 0 for b in station.scenario.bins}
    counts = {"on_belt": 0, "on_floor": 0, "elsewhere": 0}
    parts = {}
    in_world = pool.in_world(root_context)
    for name in in_world:
        place, detail = locate(station, root_context, name, held_by)
        parts[name] = f"{place}:{detail}" if detail else place
        if place == "held":
            held[detail] += 1
        elif place == "in_bin":
            in_bin[detail] += 1
        else:
            counts[place] += 1
    placed = len(station.parts) - len(station.pool)
    return Ledger(
        time=root_context.get_time(),
        spawned=pool.spawn_count + placed,
        parked=len(pool.names) - len(in_world),
        on_belt=counts["on_belt"],
        on_floor=counts["on_floor"],
        elsewhere=counts["elsewhere"],
        held=held,
        in_bin=in_bin,
        disposed=pool.dispose_count,
        parts=parts,
    )
