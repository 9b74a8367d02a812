"""A trajectory controller's ``follow_joint_trajectory`` goal, judged as ros_controllers judges it.

A goal is a trajectory (:class:`~omtp_drake.sim.trajectory_request.TrajectoryRequest`) with
path and goal tolerances and a goal time tolerance. :func:`start_goal` starts it or
says why not (``INVALID_JOINTS``, ``OLD_HEADER_TIMESTAMP``, ``INVALID_GOAL``);
:meth:`Goal.check`, called at the controller's action monitor rate, says how it stands:

- another command replaced the goal's (a new goal, a trajectory on the topic): preempted;
- before the trajectory's end, a joint farther than its path tolerance from where the
  trajectory has it: aborted, ``PATH_TOLERANCE_VIOLATED``, the joints held where they are
  commanded;
- from the trajectory's end, every joint within its goal tolerance of the last point and
  moving slower than ``stopped_velocity_tolerance``: succeeded; still outside after
  ``goal_time`` more: aborted, ``GOAL_TOLERANCE_VIOLATED``, the joints held. On ROS 2
  (``ros2=True``) a ``goal_time`` of 0 sets no limit: ROS 2's joint_trajectory_controller
  (Humble to Kilted) then waits for the goal tolerances as long as it takes.

Tolerances: the controller's ``constraints`` (``trajectory``, ``goal``, ``goal_time``,
``stopped_velocity_tolerance``), a goal's own per joint replacing them where it gives a
positive value (``-1``: none); 0 means not checked.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError
from omtp_drake.sim.ros_control import (
    Controller,
    JointNamesError,
    PastTrajectoryError,
    RosControl,
)
from omtp_drake.sim.trajectory_request import TrajectoryRequest

#: How often a ROS 2 joint_trajectory_controller judges its goal and sends feedback (its
#: ``action_monitor_rate`` parameter's default, Hz).
ACTION_MONITOR_RATE_HZ = 20.0

#: control_msgs/FollowJointTrajectoryResult's error codes.
SUCCESSFUL, INVALID_GOAL, INVALID_JOINTS, OLD_HEADER_TIMESTAMP = 0, -1, -2, -3
PATH_TOLERANCE_VIOLATED, GOAL_TOLERANCE_VIOLATED = -4, -5


@dataclass(frozen=True)
class GoalOutcome:
    """How a goal ended (``status``: ``succeeded``, ``aborted``, ``preempted``, ``rejected``)."""

    status: str
    error_code: int = SUCCESSFUL
    error_string: str = ""


def _tolerances(defaults: Mapping[str, float], given: Mapping[str, float], joints: list[str]) -> np.ndarray:
    out = []
    for joint in joints:
        value = given.get(joint, 0.0)
        out.append(0.0 if value < 0 else value if value > 0 else defaults.get(joint, 0.0))
    return np.array(out)


class Goal:
    """An accepted goal of ``controller`` (see the module doc)."""

    def __init__(
        self,
        control: RosControl,
        controller: Controller,
        tag: int,
        finish: float,
        path: Mapping[str, float],
        goal: Mapping[str, float],
        goal_time: float,
        ros2: bool = False,
    ):
        config = controller.config
        joints = list(config.joints)
        self._control = control
        self.controller = controller
        self._tag = tag
        self.finish = finish
        self._path = _tolerances({j: t.trajectory for j, t in config.tolerances.items()}, path, joints)
        self._goal = _tolerances({j: t.goal for j, t in config.tolerances.items()}, goal, joints)
        self._goal_time = goal_time if goal_time > 0 else config.goal_time
        if ros2 and self._goal_time <= 0:
            self._goal_time = float("inf")
        self.outcome: Optional[GoalOutcome] = None

    def check(self, root_context: Context) -> Optional[GoalOutcome]:
        """The goal's outcome once it has one (None: still active)."""
        if self.outcome is not None:
            return self.outcome
        control, controller = self._control, self.controller
        if control.playing(root_context, controller).tag != self._tag:
            return self._end(GoalOutcome("preempted"))
        now = root_context.get_time()
        q_d, _ = control.desired(root_context, controller)
        q, v = control.system.measured(root_context, controller.model, controller.config.joints)
        error = np.abs(q_d - q)
        if now < self.finish - 1e-9:
            bad = (self._path > 0) & (error > self._path)
            if bad.any():
                control.stop(root_context, controller)
                joint = controller.config.joints[int(np.argmax(bad))]
                return self._end(
                    GoalOutcome("aborted", PATH_TOLERANCE_VIOLATED, f"{joint} path tolerance violated")
                )
            return None
        stopped = controller.config.stopped_velocity_tolerance
        inside = (self._goal <= 0) | (error <= self._goal)
        if inside.all() and (stopped <= 0 or (np.abs(v) <= stopped).all()):
            return self._end(GoalOutcome("succeeded"))
        if now > self.finish + self._goal_time + 1e-9:
            control.stop(root_context, controller)
            joint = controller.config.joints[int(np.argmin(inside))] if not inside.all() else "a joint"
            return self._end(
                GoalOutcome("aborted", GOAL_TOLERANCE_VIOLATED, f"{joint} goal tolerance violated")
            )
        return None

    def _end(self, outcome: GoalOutcome) -> GoalOutcome:
        self.outcome = outcome
        return outcome


def start_goal(
    root_context: Context,
    control: RosControl,
    controller: Controller,
    request: TrajectoryRequest,
    path: Mapping[str, float],
    goal: Mapping[str, float],
    goal_time: float,
    ros2: bool = False,
) -> Goal | GoalOutcome:
    """The started goal, or the outcome of a rejected one (``ros2``: ROS 2's goal time rule)."""
    try:
        command = control.follow(root_context, controller, request)
    except JointNamesError as e:
        return GoalOutcome("rejected", INVALID_JOINTS, str(e))
    except PastTrajectoryError as e:
        return GoalOutcome("rejected", OLD_HEADER_TIMESTAMP, str(e))
    except ConfigError as e:
        return GoalOutcome("rejected", INVALID_GOAL, str(e))
    finish = command.spline.finish if command.spline is not None else root_context.get_time()
    return Goal(control, controller, command.tag, finish, path, goal, goal_time, ros2)
