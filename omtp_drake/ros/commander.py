"""The rest of moveit_commander and actionlib: RobotCommander, PlanningSceneInterface,
roscpp_initialize, and the ``execute_trajectory`` action client.

Planning scene. MoveIt's scene in the course holds the static cell; loose parts
are not in it. Here the scene is the static cell, the other arm, the part a
gripper holds, and the boxes a script adds with :class:`PlanningSceneInterface`
(``add_box``, ``remove_world_object``; ``attach_box`` to the gripper). It lives
in the cell (``cell.planning_scene``), so every group and plan sees it.
"""

from __future__ import annotations

import logging
from typing import Any, Optional

from omtp_drake.errors import OmtpError
from omtp_drake.ros._core import tool_frame_names
from omtp_drake.ros.convert import pose_msg, rigid
from omtp_drake.ros.interfaces import (
    AttachedCollisionObject,
    CollisionObject,
    ExecuteTrajectoryAction,
    ExecuteTrajectoryResult,
    MoveItErrorCodes,
    RobotState,
    SolidPrimitive,
)
from omtp_drake.ros.messages import Header, JointState, PoseStamped
from omtp_drake.ros.moveit import MoveGroupCommander, MoveItCommanderException
from omtp_drake.ros.moveit_config import semantics
from omtp_drake.ros.node import Time, _blocking, resolve_name
from omtp_drake.ros.session import current
from omtp_drake.ros.trajectories import joint_names
from omtp_drake.ros.unsupported import not_supported

_log = logging.getLogger("moveit_commander")


def roscpp_initialize(args: Any = None) -> None:
    """Nothing to start: the cell is the robot."""
    current()


def roscpp_shutdown() -> None:
    current()


class RobotCommander:
    """moveit_commander.RobotCommander: the groups, the planning frame, the state."""

    def __init__(self, robot_description: str = "robot_description", ns: str = ""):
        self._session = current()
        self._groups: dict[str, MoveGroupCommander] = {}

    def get_group_names(self) -> list[str]:
        """The SRDF's groups (move groups and end-effector groups)."""
        return list(semantics(self._session).groups)

    def get_group(self, name: str) -> MoveGroupCommander:
        if name not in self._groups:
            self._groups[name] = MoveGroupCommander(name)
        return self._groups[name]

    def get_planning_frame(self) -> str:
        return "world"

    def get_current_state(self) -> RobotState:
        names: list[str] = []
        positions: list[float] = []
        for robot in self._session.cell.station.arms:
            names += joint_names(robot)
            positions += [float(x) for x in self._session.cell.arm(robot).joint_values()]
        header = Header(stamp=Time.now(), frame_id="world")
        return RobotState(joint_state=JointState(header=header, name=names, position=positions))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"RobotCommander.{name}")


def _scene() -> Any:
    scene = getattr(current().cell, "planning_scene", None)
    if scene is None:
        not_supported("PlanningSceneInterface on this cell", "its Cell has no planning_scene")
    return scene


def _robot_of(link: Optional[str]) -> Optional[str]:
    """The robot whose gripper or tool link ``link`` is (None for None or "")."""
    if not link:
        return None
    cell = current().cell
    for robot in cell.station.arms:
        if link in tool_frame_names(cell.arm(robot).config).values():
            return robot
    links = [n for r in cell.station.arms for n in tool_frame_names(cell.arm(r).config).values()]
    raise MoveItCommanderException(f"{link!r} is no end-effector link; links: {', '.join(links)}")


def _object_msg(name: str, box: Any, frame: str) -> CollisionObject:
    primitive = SolidPrimitive(type=SolidPrimitive.BOX, dimensions=list(box.size))
    return CollisionObject(
        header=Header(stamp=Time.now(), frame_id=frame),
        id=name,
        primitives=[primitive],
        primitive_poses=[pose_msg(box.X)],
    )


def _world_pose(pose: Any, what: str) -> Any:
    if not isinstance(pose, PoseStamped):
        raise MoveItCommanderException(f"{what} takes a geometry_msgs PoseStamped, got {type(pose).__name__}")
    from omtp_drake.ros._core import CorePoseStamped

    frame = pose.header.frame_id.lstrip("/") or "world"
    X = rigid(pose.pose, what)
    return X if frame == "world" else current().cell.world_pose(CorePoseStamped(frame, None, X))


class PlanningSceneInterface:
    """moveit_commander.PlanningSceneInterface on the cell's planning scene."""

    def __init__(self, ns: str = "", synchronous: bool = False, service_timeout: float = 5.0):
        self._session = current()

    def add_box(self, name: str, pose: PoseStamped, size: Any = (1, 1, 1)) -> None:
        try:
            _scene().add_box(name, _world_pose(pose, "add_box"), [float(x) for x in size])
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def remove_world_object(self, name: Optional[str] = None) -> None:
        try:
            _scene().remove(name)
        except OmtpError as e:
            _log.warning("remove_world_object: %s", e)

    def attach_box(
        self,
        link: str,
        name: str,
        pose: Optional[PoseStamped] = None,
        size: Any = (1, 1, 1),
        touch_links: Any = (),
    ) -> None:
        scene = _scene()
        try:
            scene.attach_box(
                _robot_of(link),
                name,
                None if pose is None else _world_pose(pose, "attach_box"),
                [float(x) for x in size],
            )
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def remove_attached_object(self, link: Optional[str] = None, name: Optional[str] = None) -> None:
        try:
            _scene().detach(_robot_of(link), name)
        except OmtpError as e:
            _log.warning("remove_attached_object: %s", e)

    def get_known_object_names(self, with_type: bool = False) -> list[str]:
        return _scene().names()

    def get_attached_objects(self, object_ids: Any = ()) -> dict[str, AttachedCollisionObject]:
        cell = current().cell
        out = {}
        for name, box in _scene().attached().items():
            if not object_ids or name in object_ids:
                cup = f"{cell.arm(box.robot).config.gripper}_cup"
                link = tool_frame_names(cell.arm(box.robot).config)["suction_cup"]
                out[name] = AttachedCollisionObject(link_name=link, object=_object_msg(name, box, cup))
        return out

    def get_objects(self, object_ids: Any = ()) -> dict[str, CollisionObject]:
        objects = _scene().objects()
        return {
            k: _object_msg(k, v, "world") for k, v in objects.items() if not object_ids or k in object_ids
        }

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"PlanningSceneInterface.{name}")


# ----------------------------------------------------------------------------- actionlib


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
        self._result: Optional[ExecuteTrajectoryResult] = None
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
        session = self._session
        seconds = timeout.to_sec() if hasattr(timeout, "to_sec") else float(timeout or 0.0)
        limit = self._end if seconds <= 0 else min(self._end, session.time + seconds)
        if self._state == GoalStatus.ACTIVE:
            with _blocking():
                session.run_until(limit)
            if session.time >= self._end - 1e-9:
                self._state = GoalStatus.SUCCEEDED
        return self._state in (GoalStatus.SUCCEEDED, GoalStatus.ABORTED)

    def get_state(self) -> int:
        return self._state

    def get_result(self) -> Optional[ExecuteTrajectoryResult]:
        return self._result

    def cancel_goal(self) -> None:
        if self._group is not None and self._state == GoalStatus.ACTIVE:
            self._group.stop()
            self._state = GoalStatus.PREEMPTED

    cancel_all_goals = cancel_goal
