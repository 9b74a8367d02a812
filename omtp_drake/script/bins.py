"""A bin of the cell, for a script: where it is, its inner size, where a part can still go.

Example (a part dropped at the free spot falls into bin 1)::

    bin_1 = cell.bin("bin_1")
    width_x, width_y, depth = bin_1.inner_size
    part = cell.spawn_part(xyz=bin_1.drop_point())
    cell.wait(1.0)
    assert bin_1.parts() == [part]
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.errors import ConfigError, SimulationError

if TYPE_CHECKING:
    from omtp_drake.scenario import BinConfig
    from omtp_drake.sim.runtime import FactoryRuntime

#: Clearance (m) kept between a dropped part and the walls, and above the rim when dropping.
WALL_CLEARANCE = 0.01
DROP_CLEARANCE = 0.05


class Bin:
    """Bin ``config.name`` of ``cell`` (get it with ``cell.bin(name)``)."""

    def __init__(self, runtime: FactoryRuntime, config: BinConfig):
        self._runtime = runtime
        self.name = config.name
        self._geometry = config.geometry

    def pose(self) -> RigidTransform:
        """``X_WB``: the bin's base frame in world, now."""
        return self._runtime.bin_pose(self.name)

    @property
    def inner_size(self) -> tuple[float, float, float]:
        """Inside the walls: x and y widths and the depth from the bin's floor to its rim (m)."""
        g = self._geometry
        return 2 * g.inner_half_x, 2 * g.inner_half_y, g.height - g.floor_top

    def parts(self) -> list[str]:
        """The parts in the bin now (from the ledger)."""
        return sorted(
            p for p, where in self._runtime.ledger().parts.items() if where == f"in_bin:{self.name}"
        )

    def drop_point(self, part_size: Optional[float] = None) -> np.ndarray:
        """Where to release a part of edge ``part_size`` (default: the scenario's part
        size) so that it lands on the lowest free spot: a world point for the part's
        centre, ``DROP_CLEARANCE`` above the rim over the bin.

        Candidate spots are the centre and the corners of the floor area the part fits
        in; the spot whose landing height (the bin's floor, or the top of the parts
        under it) is lowest wins, the centre first on a tie.

        Raises:
            ConfigError: the part does not fit in the bin.
            SimulationError: the bin is full (a part's centre would be above the rim;
                a part may stick out over the rim by less than half its size).
        """
        size = self._runtime.scenario.pool_part_size if part_size is None else float(part_size)
        g = self._geometry
        reach = np.array([g.inner_half_x, g.inner_half_y]) - size / 2 - WALL_CLEARANCE
        if not (size > 0 and reach.min() >= 0):
            raise ConfigError(
                f"a part of {size} m does not fit in {self.name} (inner width {2 * g.inner_half_width:.3f} m)"
            )
        X_WB = self.pose()
        X_BW = X_WB.inverse()
        in_bin = [X_BW @ self._runtime.part_pose(p).translation() for p in self.parts()]
        spots = [np.zeros(2)] + [reach * np.array([sx, sy]) for sx in (-1, 1) for sy in (-1, 1)]

        def landing(spot: np.ndarray) -> float:
            under = [p[2] + size / 2 for p in in_bin if np.max(np.abs(p[:2] - spot)) < size]
            return max(under, default=g.floor_top)

        best = min(spots, key=landing)
        if landing(best) + size / 2 > g.height + 1e-9:
            raise SimulationError(
                f"{self.name} is full for a {size} m part: "
                f"{', '.join(self.parts())} leave no spot under the rim"
            )
        return X_WB @ np.array([best[0], best[1], g.height + size / 2 + DROP_CLEARANCE])
