"""Collision-aware motion planning for one arm of the cell (a MoveIt-like back end).

Modules (one job each):

- ``planner``: ``ArmPlanner``, the one facade: collisions, plans, IK, Cartesian paths, timing
- ``planner_kinematics``: ``ArmPlanner``'s kinematic queries (FK, IK, Cartesian paths), a base class
- ``collision``: the collision model of one arm in the cell (``SceneGraphCollisionChecker``)
- ``scene``: the planning scene: what the planner avoids besides the cell's own models
- ``ik``: forward and inverse kinematics of one arm, IK with seeds
- ``search``: the search for a collision-free joint path (OMPL's RRTConnect and simplifier)
- ``cartesian``: straight-line tool motions, like MoveIt's ``compute_cartesian_path``
- ``timing``: a rest-to-rest, time-optimal trajectory of a joint path (TOPP-RA)
- ``formatting``: how the planner writes joints, poses and touching pairs in its messages

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
