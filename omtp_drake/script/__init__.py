"""Scripting the cell yourself: ``Cell`` and the arms, grippers and cameras it hands out.

Modules (one job each):

- ``cell``: ``Cell``: the cell to script from a plain script or notebook
- ``arm``: ``Arm``: an arm of the cell, MoveIt-commander style (the facade a script uses)
- ``arm_commander``: ``ArmCommander``: the system that feeds an arm's servo, and ``JointCommand``
- ``motion``: an arm's moves: a ``Plan`` stepped to its end with contact checks, and ``MoveResult``
- ``scene``: MoveIt's planning scene of a cell: what the arms' plans and moves avoid
- ``devices``: the cell's vacuum grippers and logical cameras (the course's services), and waiting
- ``bins``: a bin for a script: where it is, its inner size, where a part can still go

May import: ``omtp_drake.viz``, ``omtp_drake.launch``, ``omtp_drake.sim``, ``omtp_drake.control`` and below.
(The ROS 1 layer, ``omtp_drake.ros``, sits beside this package and builds on it.)
"""

from omtp_drake.script.cell import Cell

__all__ = ["Cell"]
