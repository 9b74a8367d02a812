"""ros2_controllers' ``/<ns>/<controller>/follow_joint_trajectory`` action
(``control_msgs/action/FollowJointTrajectory``) on each trajectory controller, over
:mod:`omtp_drake.sim.trajectory_goals`' rules (tolerances, outcomes, error codes).

``control_msgs`` has no PyPI package: it is built here (:mod:`omtp_drake.ros2.interface_build`).
A goal the layer refuses (unknown joints, a past stamp, a bad trajectory) is rejected, as the
joint_trajectory_controller rejects it, with one error line; an accepted goal starts at once, is
judged at the layer's action monitor rate on the cell's thread, with feedback (desired, actual,
error) at that rate, and ends succeeded, aborted (its error code and string) or canceled (a
cancel request: the joints held). A goal replaced by another command (a new goal, a trajectory
on ``~/joint_trajectory``) ends aborted with ``SUCCESSFUL``: rclpy cannot cancel a goal nobody
asked to cancel.
"""

from __future__ import annotations

import collections
import concurrent.futures
import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from omtp_drake.gazebo.schedule import topic
from omtp_drake.ros2 import messages
from omtp_drake.sim.ros_control import Controller, Periodic, RosControl
from omtp_drake.sim.trajectory_goals import ACTION_MONITOR_RATE_HZ, Goal, GoalOutcome, start_goal

if TYPE_CHECKING:
    from omtp_drake.script import Cell

_log = logging.getLogger("ros2_control")

OnCell = Callable[[Callable[[], None]], None]

#: Wall-clock seconds a goal request waits for the cell's thread before it is rejected.
_PATIENCE = 60.0


class FollowJointTrajectoryServers:
    """The action of each trajectory controller of ``control`` on ``node``; ``on_cell(work)``
    queues ``work`` for the cell's thread (between steps)."""

    def __init__(
        self, node: Any, cell: Cell, control: RosControl, on_cell: Callable[[Callable[[], None]], None]
    ):
        from control_msgs.action import FollowJointTrajectory
        from rclpy.action import ActionServer, CancelResponse

        self._node = node
        self._cell = cell
        self._control = control
        self._on_cell = on_cell
        self._action = FollowJointTrajectory
        self._monitor = Periodic(1.0 / ACTION_MONITOR_RATE_HZ)
        #: Accepted goals not executing yet, in order (rclpy executes them in the order accepted).
        self._accepted: collections.deque[Goal] = collections.deque()
        #: Executing goals: (goal, the rclpy future of its outcome, its goal handle).
        self._active: list[tuple[Goal, Any, Any]] = []
        self.servers: list[Any] = []
        for controller in control.of_kind("trajectory"):
            name = topic(controller.namespace, f"{controller.name}/follow_joint_trajectory")
            self.servers.append(
                ActionServer(
                    node,
                    FollowJointTrajectory,
                    name,
                    execute_callback=self._execute,
                    goal_callback=lambda request, c=controller: self._accept(c, request),
                    cancel_callback=lambda _goal: CancelResponse.ACCEPT,
                )
            )

    def _accept(self, controller: Controller, request: Any) -> Any:
        """Starts the goal on the cell's thread; accepted, or rejected with the layer's reason."""
        from rclpy.action import GoalResponse

        started: concurrent.futures.Future[Goal | GoalOutcome] = concurrent.futures.Future()

        def work() -> None:
            started.set_result(
                start_goal(
                    self._cell.runtime.context,
                    self._control,
                    controller,
                    messages.trajectory_request(request.trajectory),
                    {t.name: t.position for t in request.path_tolerance},
                    {t.name: t.position for t in request.goal_tolerance},
                    messages.seconds(request.goal_time_tolerance),
                    ros2=True,
                )
            )

        self._on_cell(work)
        try:
            goal = started.result(timeout=_PATIENCE)
        except concurrent.futures.TimeoutError:
            _log.error("%s: the cell did not take the goal within %.0f s", controller.name, _PATIENCE)
            return GoalResponse.REJECT
        if isinstance(goal, GoalOutcome):
            _log.error("%s: goal rejected: %s", controller.name, goal.error_string)
            return GoalResponse.REJECT
        self._accepted.append(goal)
        return GoalResponse.ACCEPT

    async def _execute(self, goal_handle: Any) -> Any:
        from rclpy.task import Future

        # The executor's future, with a callback: its result, set on the cell's thread, wakes the
        # executor to resume this coroutine.
        done: Future[GoalOutcome] = Future(executor=self._node.executor)
        done.add_done_callback(lambda _f: None)
        goal = self._accepted.popleft()
        self._on_cell(lambda: self._active.append((goal, done, goal_handle)))
        outcome: GoalOutcome = await done
        if outcome.status == "succeeded":
            goal_handle.succeed()
        elif outcome.status == "canceled":
            goal_handle.canceled()
        else:
            goal_handle.abort()
        return self._action.Result(error_code=outcome.error_code, error_string=outcome.error_string)

    def check(self, now: float) -> None:
        """On the cell's thread at ``now``: each active goal's feedback and outcome, at the
        action monitor rate."""
        if not self._active or not self._monitor.due(now):
            return
        context = self._cell.runtime.context
        still = []
        for goal, done, handle in self._active:
            if handle.is_cancel_requested:
                self._control.stop(context, goal.controller)
                outcome: GoalOutcome | None = GoalOutcome("canceled")
            else:
                outcome = goal.check(context)
            if outcome is None:
                handle.publish_feedback(self._feedback(goal, now))
                still.append((goal, done, handle))
            else:
                done.set_result(outcome)
        self._active = still

    def _feedback(self, goal: Goal, now: float) -> Any:
        context, controller = self._cell.runtime.context, goal.controller
        q_d, v_d = self._control.desired(context, controller)
        q, v = self._control.system.measured(context, controller.model, controller.config.joints)
        return self._action.Feedback(
            header=messages.header(now),
            joint_names=list(controller.config.joints),
            desired=_point(q_d, v_d),
            actual=_point(q, v),
            error=_point(q_d - q, v_d - v),
        )


def _point(q: Any, v: Any) -> Any:
    from trajectory_msgs.msg import JointTrajectoryPoint

    return JointTrajectoryPoint(positions=[float(x) for x in q], velocities=[float(x) for x in v])
