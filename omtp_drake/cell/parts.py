"""Where parts are put: parking slots far from the cell and the spawner's poses.

Drake cannot add bodies to a built plant, so every part that may ever appear
is in the plant from the start: the scenario's placed parts and a pool of
``object_1 ... object_N``. A part out of the world is *parked*: far from the
cell (a row at x = 50 m) with its floating joint locked (no motion, no contact,
no cost in the contact solver). Spawning unlocks the next parked pool part and
puts it at the spawn pose; disposal parks a part again. The pool's bookkeeping
while the cell runs is :class:`omtp_drake.sim.pool.PartPool`.
"""

# No `from __future__ import annotations`: SpawnerConfig is a YAML schema.

import logging
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.scenario.configs import SpawnerConfig

if TYPE_CHECKING:
    pass

_log = logging.getLogger(__name__)

#: Where parked part k waits (x = PARK_X0 + k * PARK_DX, on a line far from the cell).
PARK_X0, PARK_DX, PARK_Y, PARK_Z = 50.0, 0.5, 50.0, 1.0


def parking_pose(slot: int) -> RigidTransform:
    """``X_WP`` of the part parked in ``slot`` (its index among all parts)."""
    return RigidTransform([PARK_X0 + slot * PARK_DX, PARK_Y, PARK_Z])


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
