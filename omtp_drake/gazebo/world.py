"""The world the Gazebo plugins of a cell share: its models under Gazebo's names
(:class:`~omtp_drake.gazebo.models.GazeboModels`, renamed by the spawn services) and its
physics updates.

A Gazebo world plugin runs at every world update (``ConnectWorldUpdateBegin``); here a
physics update is one plant step (``plant_config.time_step``). The updates are hooked into
the cell's driver the first time a plugin needs them (:meth:`GazeboWorld.start_updates`),
so a cell nobody asks for them pays nothing; from then on every hook runs at every update,
on the cell's thread, with the simulated time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from omtp_drake.gazebo.models import GazeboModels

if TYPE_CHECKING:
    from omtp_drake.script import Cell


class GazeboWorld:
    """``cell``'s Gazebo world (see the module doc): one per transport's run."""

    def __init__(self, cell: Cell):
        self.cell = cell
        self.models = GazeboModels(cell)
        #: Called at every physics update (after the plant's step), with the time.
        self.update_hooks: list[Callable[[float], None]] = []
        self._updating = False

    @property
    def update_period(self) -> float:
        """The physics update period (s): the plant's time step."""
        return float(self.cell.scenario.plant_config.time_step)

    def start_updates(self) -> None:
        """From now on the update hooks run at every physics update."""
        if not self._updating:
            self._updating = True
            self.cell.runtime.driver.every(self.update_period, self._on_update)

    def _on_update(self) -> None:
        t = self.cell.time
        for hook in list(self.update_hooks):
            hook(t)
