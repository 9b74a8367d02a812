"""Collision-aware motion planning for one arm of the cell (a MoveIt-like back end).

:class:`ArmPlanner` (:mod:`~omtp_drake.control.motion.planner`) is the one facade;
the modules beside it hold one concept each: the collision model (``collision``),
the planning scene's edits (``scene``), IK (``ik``), the OMPL search (``search``),
Cartesian paths (``cartesian``) and TOPP-RA timing (``timing``).

Modules here import each other by module (``omtp_drake.control.motion.ik``), never
through this package.
"""

from omtp_drake.control.motion.collision import OtherPositions
from omtp_drake.control.motion.planner import DEFAULT_EDGE_STEP, ArmPlanner
from omtp_drake.control.motion.scene import Obstacle
from omtp_drake.control.motion.timing import ACCELERATION_LIMITS, time_parameterize

__all__ = [
    "ACCELERATION_LIMITS",
    "DEFAULT_EDGE_STEP",
    "ArmPlanner",
    "Obstacle",
    "OtherPositions",
    "time_parameterize",
]
