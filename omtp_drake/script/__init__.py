"""Scripting the cell yourself: ``Cell`` and the arms, grippers and cameras it hands out.

May import: ``omtp_drake.viz``, ``omtp_drake.sim``, ``omtp_drake.control`` and below.
(The ROS 1 layer, ``omtp_drake.ros``, sits beside this package and builds on it.)
"""

from omtp_drake.script.cell import Cell

__all__ = ["Cell"]
