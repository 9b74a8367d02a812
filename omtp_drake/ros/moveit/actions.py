"""actionlib's SimpleActionClient for MoveIt's ``execute_trajectory`` action, and GoalStatus.

(The ``move_group`` action's client is :mod:`omtp_drake.ros.moveit.move_group`; the
``actionlib`` shim picks the one a script asks for.)
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.ros.comm.client import resolve_name
from omtp_drake.ros.comm.interfaces import ExecuteTrajectoryAction, ExecuteTrajectoryResult, MoveItErrorCodes
from omtp_drake.ros.comm.messages import Message
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.commander import MoveGroupCommander, MoveItCommanderException
from omtp_drake.ros.moveit.config import semantics
from omtp_drake.ros.moveit.trajectories import joint_names


class GoalStatus:
    PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED = 0, 1, 2, 3, 4, 5
    LOST = 9


#: The action servers of the cell (MoveIt's move_group serves execute_trajectory).
ACTION_SERVERS = ("/execute_trajectory", "/move_group/execute_trajectory")


class SimpleActionClient:
    """actionlib.SimpleActionClient for MoveIt's ``execute_trajectory`` action.

    ``send_goal`` starts the trajectory on the arm whose joints it names (the
    motion runs as simulated time advances); ``wait_for_result`` advances time
    until it has finished (or ``timeout``); ``get_result`` gives its error code.
    """

    def __init__(self, ns: str, ActionSpec: Any):  # noqa: N803 (actionlib's name)
        if resolve_name(ns) not in ACTION_SERVERS:
            not_supported(
                f"the action server {ns!r} (resolved: {resolve_name(ns)})",
                "the cell serves " + ", ".join(ACTION_SERVERS) + " and /move_group",
            )
        if ActionSpec is not ExecuteTrajectoryAction:
            not_supported(
                f"action type {getattr(ActionSpec, '_type', ActionSpec)}", "use ExecuteTrajectoryAction"
            )
        self._session = current()
        self._state = GoalStatus.LOST
        self._end = 0.0
        self._result: Optional[Message] = None
        self._group: Optional[MoveGroupCommander] = None

    def wait_for_server(self, timeout: Any = None) -> bool:
        return True

    def send_goal(
        self, goal: Any, done_cb: Any = None, active_cb: Any = None, feedback_cb: Any = None
    ) -> None:
        if done_cb is not None or feedback_cb is not None:
            not_supported("send_goal callbacks", "call wait_for_result")
        names = goal.trajectory.joint_trajectory.joint_names
        robot = next((r for r in self._session.cell.station.arms if joint_names(r)[0] in names), None)
        if robot is None:
            raise MoveItCommanderException(f"the goal's joints {names} belong to no arm of the cell")
        group = semantics(self._session).group_of(robot)
        if group is None:
            raise MoveItCommanderException(f"the goal's joints {names} belong to no move group of the SRDF")
        self._group = MoveGroupCommander(group)
        ok = self._group.execute(goal.trajectory, wait=False)
        code = MoveItErrorCodes.SUCCESS if ok else MoveItErrorCodes.CONTROL_FAILED
        self._result = ExecuteTrajectoryResult(error_code=MoveItErrorCodes(code))
        self._state = GoalStatus.ACTIVE if ok else GoalStatus.ABORTED
        self._end = self._group._motion_end if ok else self._session.time

    def send_goal_and_wait(self, goal: Any, execute_timeout: Any = None, preempt_timeout: Any = None) -> int:
        self.send_goal(goal)
        self.wait_for_result(execute_timeout)
        return self.get_state()

    def wait_for_result(self, timeout: Any = None) -> bool:
        """Advances time until the motion has ended and the arm stopped (MoveIt's
        ``waitForRobotToStop``), or ``timeout``."""
        seconds = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
        if self._state == GoalStatus.ACTIVE and self._group is not None:
            self._group._wait_for_motion(seconds)
            if self._group._motion_done():
                self._state = GoalStatus.SUCCEEDED
        return self._state in (GoalStatus.SUCCEEDED, GoalStatus.ABORTED)

    def get_state(self) -> int:
        return self._state

    def get_result(self) -> Optional[Message]:
        return self._result

    def cancel_goal(self) -> None:
        if self._group is not None and self._state == GoalStatus.ACTIVE:
            self._group.stop()
            self._state = GoalStatus.PREEMPTED

    cancel_all_goals = cancel_goal
