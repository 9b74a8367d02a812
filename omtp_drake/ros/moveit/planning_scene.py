"""moveit_commander's PlanningSceneInterface (``moveit_commander.planning_scene_interface``).

MoveIt's scene in the course holds the static cell; loose parts are not in it.
Here the scene is the static cell, the other arm, the part a gripper holds, and
the boxes a script adds (``add_box``, ``remove_world_object``; ``attach_box`` to
the gripper). It lives in the cell (``cell.planning_scene``), so every group and
plan sees it.
"""

from __future__ import annotations

import logging
from typing import Any, Optional

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm._core import tool_frame_names
from omtp_drake.ros.comm.interfaces import AttachedCollisionObject, CollisionObject, SolidPrimitive
from omtp_drake.ros.comm.messages import Header, Message, PoseStamped
from omtp_drake.ros.comm.rostime import Time
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.commander import MoveItCommanderException
from omtp_drake.ros.tf.convert import pose_msg, rigid

_log = logging.getLogger("moveit_commander")


def scene_of_run() -> Any:
    """The run's cell's planning scene (CellPlanningScene)."""
    scene = getattr(current().cell, "planning_scene", None)
    if scene is None:
        not_supported("PlanningSceneInterface on this cell", "its Cell has no planning_scene")
    return scene


def robot_of_link(link: Optional[str]) -> Optional[str]:
    """The robot whose gripper or tool link ``link`` is (None for None or "")."""
    if not link:
        return None
    cell = current().cell
    for robot in cell.station.arms:
        if link in tool_frame_names(cell.arm(robot).config).values():
            return robot
    links = [n for r in cell.station.arms for n in tool_frame_names(cell.arm(r).config).values()]
    raise MoveItCommanderException(f"{link!r} is no end-effector link; links: {', '.join(links)}")


def _object_msg(name: str, box: Any, frame: str) -> Message:
    primitive = SolidPrimitive(type=SolidPrimitive.BOX, dimensions=list(box.size))
    return CollisionObject(
        header=Header(stamp=Time.now(), frame_id=frame),
        id=name,
        primitives=[primitive],
        primitive_poses=[pose_msg(box.X)],
    )


def world_pose_of(pose: Any, what: str) -> Any:
    """``X_W``: a PoseStamped (any tf frame, now) as a world pose; MoveItCommanderException otherwise."""
    if not isinstance(pose, PoseStamped):
        raise MoveItCommanderException(f"{what} takes a geometry_msgs PoseStamped, got {type(pose).__name__}")
    from omtp_drake.ros.comm._core import CorePoseStamped

    frame = pose.header.frame_id.lstrip("/") or "world"
    X = rigid(pose.pose, what)
    return X if frame == "world" else current().cell.world_pose(CorePoseStamped(frame, None, X))


class PlanningSceneInterface:
    """moveit_commander.PlanningSceneInterface on the cell's planning scene."""

    def __init__(self, ns: str = "", synchronous: bool = False, service_timeout: float = 5.0):
        self._session = current()

    def add_box(self, name: str, pose: Message, size: Any = (1, 1, 1)) -> None:
        try:
            scene_of_run().add_box(name, world_pose_of(pose, "add_box"), [float(x) for x in size])
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def remove_world_object(self, name: Optional[str] = None) -> None:
        try:
            scene_of_run().remove(name)
        except OmtpError as e:
            _log.warning("remove_world_object: %s", e)

    def attach_box(
        self,
        link: str,
        name: str,
        pose: Optional[Message] = None,
        size: Any = (1, 1, 1),
        touch_links: Any = (),
    ) -> None:
        scene = scene_of_run()
        try:
            scene.attach_box(
                robot_of_link(link),
                name,
                None if pose is None else world_pose_of(pose, "attach_box"),
                [float(x) for x in size],
            )
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def remove_attached_object(self, link: Optional[str] = None, name: Optional[str] = None) -> None:
        try:
            scene_of_run().detach(robot_of_link(link), name)
        except OmtpError as e:
            _log.warning("remove_attached_object: %s", e)

    def get_known_object_names(self, with_type: bool = False) -> list[str]:
        return scene_of_run().names()

    def get_attached_objects(self, object_ids: Any = ()) -> dict[str, Message]:
        cell = current().cell
        out = {}
        for name, box in scene_of_run().attached().items():
            if not object_ids or name in object_ids:
                cup = f"{cell.arm(box.robot).config.gripper}_cup"
                link = tool_frame_names(cell.arm(box.robot).config)["suction_cup"]
                out[name] = AttachedCollisionObject(link_name=link, object=_object_msg(name, box, cup))
        return out

    def get_objects(self, object_ids: Any = ()) -> dict[str, Message]:
        objects = scene_of_run().objects()
        return {
            k: _object_msg(k, v, "world") for k, v in objects.items() if not object_ids or k in object_ids
        }

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"PlanningSceneInterface.{name}")
