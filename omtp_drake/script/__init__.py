"""Scripting the cell yourself: ``Cell`` and the arms, grippers and cameras it hands out.

Lives here: the cell to script (``cell``), its arms, their plans and moves and
the system that commands them (``arm``), its vacuum grippers and logical
cameras (``devices``).

May import: ``omtp_drake.viz``, ``omtp_drake.sim``, ``omtp_drake.control`` and below.
(The ROS 1 layer, ``omtp_drake.ros``, sits beside this package and builds on it.)
"""

from omtp_drake.script.cell import Cell

__all__ = ["Cell"]
