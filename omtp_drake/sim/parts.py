"""The course's part services on a running cell: spawn, write off, knock, remove
a part, read where parts are, take the ledger.

:class:`PartServices` is the part of :class:`~omtp_drake.sim.runtime.FactoryRuntime`
that deals with parts; the runtime builds the station, its Context and the part
pool these methods read and edit.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity
from pydrake.systems.framework import Context

from omtp_drake.cell.station import Station
from omtp_drake.errors import ConfigError, SimulationError, UnknownNameError, check_vector
from omtp_drake.scenario import Scenario, check_in_cell
from omtp_drake.sim.driver import loose_parts, spawn
from omtp_drake.sim.ledger import Ledger, take_ledger
from omtp_drake.sim.pool import PartPool


class PartServices:
    """Spawning, removing and reading parts (a base of FactoryRuntime, which sets
    the attributes below)."""

    scenario: Scenario
    station: Station
    context: Context
    pool: PartPool
    _plant_context: Context

    def spawn_part(self, xyz: Optional[Sequence[float]] = None, yaw: Optional[float] = None) -> str:
        """Spawns the next parked part; returns its name.

        Without ``xyz``/``yaw`` the scenario's spawner pose (plus its seeded
        variance) is used. With the spawner's ``one_at_a_time`` (the course's
        ``spawn_object_once``), spawning while another part is loose in the
        world (not in a bin) raises SimulationError.
        """
        if xyz is not None:
            check_in_cell("spawn_part xyz", check_vector("spawn_part xyz", xyz))
        if yaw is not None and not math.isfinite(yaw):
            raise ConfigError(f"spawn_part yaw must be finite, got {yaw!r}")
        spawner = self.scenario.spawner
        if spawner is not None and spawner.one_at_a_time:
            loose = loose_parts(self.station, self.context, self.pool)
            if loose:
                raise SimulationError(f"one part at a time: {', '.join(loose)} is still in the world")
        return spawn(self.station, self.context, self.pool, xyz, yaw)

    def write_off_part(self, name: str) -> None:
        """Gives up on part ``name`` (lost where nobody can pick it): it stays where it
        is and in the ledger, but no longer holds a one-at-a-time spawner back, and the
        spawner replaces it."""
        self.pool.write_off(self.context, name)

    def knock_part(self, name: str, velocity: Sequence[float]) -> None:
        """Fault injection: part ``name`` is knocked: it moves off at ``velocity``
        (m/s, world) and then slides, tumbles or falls as physics has it."""
        self.pool.check_in_world(self.context, name)
        v = np.array(check_vector("knock_part velocity (m/s)", velocity, max_norm=20.0))
        plant = self.station.plant
        self.station.part_states.wake(self.context, name)
        body = plant.GetBodyByName(name, self.station.parts[name])
        plant.SetFreeBodySpatialVelocity(self._plant_context, body, SpatialVelocity(np.zeros(3), v))

    def remove_part(self, name: str) -> None:
        """Disposes of a part in the world now (as the deletion wall does)."""
        self.pool.dispose(self.context, name)

    def part_pose(self, name: str) -> RigidTransform:
        """Ground-truth world pose of a part (for tests and plots, not for controllers)."""
        if name not in self.station.parts:
            raise UnknownNameError("part", name, self.station.parts)
        plant = self.station.plant
        return plant.EvalBodyPoseInWorld(
            self._plant_context, plant.GetBodyByName(name, self.station.parts[name])
        )

    def parts_in_world(self) -> list[str]:
        """Placed parts and spawned parts not disposed of."""
        return self.pool.in_world(self.context)

    def ledger(self) -> Ledger:
        """Where every part that entered the world is now."""
        return take_ledger(self.station, self.context, self.pool)
