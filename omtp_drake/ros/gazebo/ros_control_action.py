"""actionlib's SimpleActionClient for a ros_control trajectory controller's ``follow_joint_trajectory``.

``SimpleActionClient('/<ns>/<controller>/follow_joint_trajectory', FollowJointTrajectoryAction)``
(the ``actionlib`` shim picks this client for that type). What a goal does and how it ends is
:mod:`omtp_drake.sim.trajectory_goals`'s; here the action's states and result. The goal is
judged whenever the script asks (``wait_for_result`` asks after each tick of the session,
``get_state`` and ``get_result`` when called): a path tolerance is checked at those moments.
"""

from __future__ import annotations

import math
from typing import Any, Optional

from omtp_drake.ros.comm._core import Controller, Goal, GoalOutcome, RosControl, start_goal
from omtp_drake.ros.comm._core import gazebo_topic as topic
from omtp_drake.ros.comm.client import resolve_name
from omtp_drake.ros.comm.control_interfaces import FollowJointTrajectoryAction, FollowJointTrajectoryResult
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.gazebo.ros_control_topics import trajectory_request

#: actionlib_msgs/GoalStatus of each outcome.
STATES = {"active": 1, "preempted": 2, "succeeded": 3, "aborted": 4, "rejected": 5}
LOST = 9


def follow_joint_trajectory_servers(control: RosControl) -> dict[str, Controller]:
    """Action name -> its trajectory controller."""
    return {topic(c.namespace, f"{c.name}/follow_joint_trajectory"): c for c in control.of_kind("trajectory")}


def is_follow_joint_trajectory(action_spec: Any) -> bool:
    return action_spec is FollowJointTrajectoryAction


class FollowJointTrajectoryClient:
    """The client of one trajectory controller's action (see the module doc)."""

    def __init__(self, ns: str):
        self._session = current()
        self._control = RosControl(self._session.cell.station)
        servers = follow_joint_trajectory_servers(self._control)
        name = resolve_name(ns)
        if name not in servers:
            not_supported(
                f"the action server {ns!r} (resolved: {name})",
                "the trajectory controllers serve " + (", ".join(servers) or "none (no controller started)"),
            )
        self._controller = servers[name]
        self._goal: Optional[Goal] = None
        self._outcome: Optional[GoalOutcome] = None

    def wait_for_server(self, timeout: Any = None) -> bool:
        return True

    def send_goal(
        self, goal: Any, done_cb: Any = None, active_cb: Any = None, feedback_cb: Any = None
    ) -> None:
        if done_cb is not None or feedback_cb is not None or active_cb is not None:
            not_supported("send_goal callbacks", "call wait_for_result")
        if self._goal is not None and self._state() == "active":
            self.cancel_goal()
        started = start_goal(
            self._session.cell.runtime.context,
            self._control,
            self._controller,
            trajectory_request(goal.trajectory),
            {t.name: t.position for t in goal.path_tolerance},
            {t.name: t.position for t in goal.goal_tolerance},
            _seconds(goal.goal_time_tolerance),
        )
        self._goal, self._outcome = (started, None) if isinstance(started, Goal) else (None, started)

    def send_goal_and_wait(self, goal: Any, execute_timeout: Any = None, preempt_timeout: Any = None) -> int:
        self.send_goal(goal)
        self.wait_for_result(execute_timeout)
        return self.get_state()

    def _state(self) -> str:
        if self._goal is not None:
            outcome = self._goal.check(self._session.cell.runtime.context)
            if outcome is not None:
                self._outcome = outcome
        if self._outcome is not None:
            return self._outcome.status
        return "active" if self._goal is not None else "lost"

    def wait_for_result(self, timeout: Any = None) -> bool:
        """Advances simulated time until the goal has an outcome, or ``timeout`` (0: no limit)."""
        seconds = _seconds(timeout) if timeout is not None else 0.0
        end = self._session.time + seconds if seconds > 0 else math.inf
        if self._state() == "lost":
            return False
        return self._session.run_until(end, until=lambda: self._state() != "active")

    def get_state(self) -> int:
        return STATES.get(self._state(), LOST)

    def get_result(self) -> Optional[Any]:
        self._state()
        if self._outcome is None:
            return None
        return FollowJointTrajectoryResult(
            error_code=self._outcome.error_code, error_string=self._outcome.error_string
        )

    def get_goal_status_text(self) -> str:
        self._state()
        return self._outcome.error_string if self._outcome is not None else ""

    def cancel_goal(self) -> None:
        if self._goal is not None and self._state() == "active":
            self._control.stop(self._session.cell.runtime.context, self._controller)
            self._outcome = self._goal.check(self._session.cell.runtime.context)

    cancel_all_goals = cancel_goal


def _seconds(value: Any) -> float:
    return value.to_sec() if hasattr(value, "to_sec") else float(value or 0.0)
