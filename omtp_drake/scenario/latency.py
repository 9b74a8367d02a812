"""The simulated time a ROS script's calls take (part of the scenario YAML schema).

In the course's cell, Gazebo keeps running while a script waits for MoveIt to
plan, for a trajectory to start or for a service to answer. ``ros-run`` runs the
cell only inside blocking calls, so it lets this much simulated time pass in
each such call, the same every run (fixed values: no wall clock, no
randomness). Gazebo runs with the wall clock when it keeps up (the course's
world lets it run up to twice as fast: ``max_step_size`` 0.001 s at
``real_time_update_rate`` 2000 Hz), so a wall-time delay of the course is taken
as the same simulated time here (real-time factor 1).

Where each default comes from:

* ``plan`` (0.08 s): ``go()`` and ``plan()`` send move_group a MoveGroup action
  goal; its OMPL pipeline (the course's ``omtp_moveit_config``: RRTConnect,
  ``longest_valid_segment_fraction`` 0.005, the request adapters
  AddTimeParameterization and FixStartState*) solves, simplifies the path
  (OMPL's ``simplifySolution``), times it and answers. RRTConnect stops at its
  first solution, so moveit_commander's ``allowed_planning_time`` (5 s,
  ``MoveGroupInterface::DEFAULT_ALLOWED_PLANNING_TIME``) is a limit, not the time
  taken. Published move_group logs of 6-joint arms show solves of 7-21 ms,
  simplifications of 3-7 ms and, for UR arms, 19 and 53 ms from request to
  plan; the course's scene (two UR5s and the cell's meshes, Gazebo on the same
  machine) is heavier, hence 80 ms.
* ``execute`` (0.025 s): from an execute request (``execute()``, the
  ``execute_trajectory`` action, or the execution half of ``go()``) to the
  trajectory's start: MoveIt's ``TrajectoryExecutionManager::validate`` waits for
  a joint state stamped after the request (``waitForCurrentState(now)``), which
  the course's ``joint_state_controller`` publishes at 50 Hz (up to 20 ms), then
  the FollowJointTrajectory goal reaches the ros_control controller, which starts
  at its next update. ``go()`` then takes 105 ms from call to motion, as a
  published UR log's 104 ms from "Combined planning and execution request
  received" to the controller hand-off.
* ``cartesian`` (0.03 s): ``compute_cartesian_path`` is a GetCartesianPath
  service call to move_group: an IK solve (trac_ik, the course's
  ``kinematics_solver_timeout`` 5 ms) and a collision check per ``eef_step``,
  then time parameterization: about 1 ms a centimetre for the course's 20-30 cm
  moves.
* ``service`` (0.005 s): a rospy ``ServiceProxy`` call (``persistent=False`` by
  default) looks the service up at the master (XML-RPC), opens a TCP connection,
  exchanges connection headers and sends the request; Gazebo's ROS thread runs
  the handler. Here the handler runs at the end of this time (the reply's way
  back is one small message).

A failed plan takes the same ``plan`` time (MoveIt may spend up to
``allowed_planning_time`` on a goal it cannot reach).
"""

import dataclasses
import math
from dataclasses import dataclass

from omtp_drake.errors import ConfigError

#: The longest delay a call may take [s].
MAX_LATENCY = 10.0


@dataclass
class RosLatencyConfig:
    """Simulated seconds a ROS script's calls take under ``ros-run`` (see the module doc).

    Attributes:
        plan: a planning request (``go()``'s planning half, ``plan()``) [s].
        execute: from an execute request to the trajectory's start (``execute()``,
            the ``execute_trajectory`` action, ``go()``'s execution half) [s].
        cartesian: a ``compute_cartesian_path`` call [s].
        service: a ``rospy.ServiceProxy`` call, before its handler runs [s].
    """

    plan: float = 0.08
    execute: float = 0.025
    cartesian: float = 0.03
    service: float = 0.005

    def validate(self) -> None:
        """Raises :class:`ConfigError` naming a field that is no number in [0, MAX_LATENCY] s."""
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ConfigError(f"ros_latency.{f.name} must be seconds, got {value!r}")
            if not (math.isfinite(value) and 0.0 <= value <= MAX_LATENCY):
                raise ConfigError(f"ros_latency.{f.name} must be in [0, {MAX_LATENCY:g}] s, got {value!r}")

    def scaled(self, factor: float) -> "RosLatencyConfig":
        """Every delay times ``factor`` (0: calls take no simulated time)."""
        if not (math.isfinite(factor) and factor >= 0):
            raise ConfigError(f"the latency factor must be a finite number >= 0, got {factor!r}")
        values = {f.name: getattr(self, f.name) * factor for f in dataclasses.fields(self)}
        scaled = RosLatencyConfig(**values)
        scaled.validate()
        return scaled


def latency_names() -> list[str]:
    """The names of the delays (``plan``, ``execute``...)."""
    return [f.name for f in dataclasses.fields(RosLatencyConfig)]
