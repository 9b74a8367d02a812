"""moveit_python (the pure-Python MoveIt client the course's FlexBE states import) on the cell.

``MoveGroupInterface(group, frame, listener=None, plan_only=False,
move_group="move_group")`` sends ``/move_group`` goals
(:mod:`omtp_drake.ros.moveit.move_group`) built as moveit_python builds them:

- ``moveToJointPosition(joints, positions, tolerance=0.01, wait=True, **kwargs)``:
  one joint constraint per joint, ``tolerance`` above and below (MoveIt's bounds
  rules apply: :mod:`omtp_drake.ros.moveit.bounds`);
- ``moveToPose(pose_stamped, gripper_frame, tolerance=0.01, wait=True, **kwargs)``:
  the pose transformed into ``frame`` with tf, then a position constraint (a sphere
  of radius ``tolerance**2``, as moveit_python writes it) and an orientation
  constraint (``tolerance`` rad per axis) on ``gripper_frame`` in ``frame``; the
  cell reaches the pose exactly.

Their keyword arguments are moveit_python's (``max_velocity_scaling_factor``,
``planner_id``, ``planning_time``, ``plan_only``, ``start_state``, ``num_attempts``,
and ``planning_scene_diff`` for joint goals); any other is logged as "unsupported
argument" and ignored, as moveit_python does. With ``wait`` they return the
action's ``moveit_msgs/MoveGroupResult`` once the arm has stopped, else None
(``get_move_action()`` is the action client to wait on).

``PlanningSceneInterface(frame, ns="", init_from_service=True)`` edits the cell's
planning scene (the one moveit_commander's interface edits): boxes at ``x, y, z``
in ``frame`` (``addBox``, ``addCube``, ``addSolidPrimitive`` with a BOX), boxes
attached to a gripper link at ``x, y, z`` in that link (``attachBox``), their
removal (a detached box goes back into the world, as in MoveIt) and the names it
knows. Other shapes and meshes raise NotSupportedError;
colours (``setColor``, ``sendColors``) are RViz's and change nothing here. Changes
apply at once, so ``waitForSync`` returns at once.
"""

from __future__ import annotations

import logging
from typing import Any, Optional

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm.interfaces import SolidPrimitive
from omtp_drake.ros.comm.messages import Header, Pose, PoseStamped
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.commander import MoveItCommanderException
from omtp_drake.ros.moveit.interfaces import (
    BoundingVolume,
    Constraints,
    JointConstraint,
    MoveGroupAction,
    MoveGroupGoal,
    OrientationConstraint,
    PositionConstraint,
)
from omtp_drake.ros.moveit.move_group import MoveGroupClient, is_move_group
from omtp_drake.ros.moveit.planning_scene import robot_of_link, scene_of_run, world_pose_of
from omtp_drake.ros.tf.listener import TransformListener

_log = logging.getLogger("rospy")

#: The keyword arguments moveit_python reads (its own list, plus ``num_attempts``, which it reads too).
_JOINT_ARGS = (
    "max_velocity_scaling_factor",
    "planner_id",
    "planning_scene_diff",
    "planning_time",
    "plan_only",
    "start_state",
)
_POSE_ARGS = ("max_velocity_scaling_factor", "planner_id", "planning_time", "plan_only", "start_state")


class MoveGroupInterface:
    """moveit_python.MoveGroupInterface on the cell's ``/move_group`` (see the module doc)."""

    def __init__(
        self,
        group: str,
        frame: str,
        listener: Any = None,
        plan_only: bool = False,
        move_group: str = "move_group",
    ):
        if not is_move_group(move_group, MoveGroupAction):
            not_supported(f"the move_group action server {move_group!r}", "the cell serves move_group")
        self._group = group
        self._fixed_frame = frame
        self._action = MoveGroupClient(move_group)
        self._listener = TransformListener() if listener is None else listener
        self.plan_only = plan_only
        self.planner_id: Optional[str] = None
        self.planning_time = 15.0

    def get_move_action(self) -> MoveGroupClient:
        return self._action

    def setPlannerId(self, planner_id: Any) -> None:  # noqa: N802 (moveit_python's names)
        self.planner_id = str(planner_id)

    def setPlanningTime(self, time: float) -> None:  # noqa: N802
        self.planning_time = time

    def moveToJointPosition(  # noqa: N802
        self, joints: Any, positions: Any, tolerance: float = 0.01, wait: bool = True, **kwargs: Any
    ) -> Any:
        _log_unsupported("moveToJointPosition", kwargs, _JOINT_ARGS)
        if len(joints) != len(positions):
            raise MoveItCommanderException(
                f"moveToJointPosition: {len(joints)} joints but {len(positions)} positions"
            )
        goal = self._goal(kwargs)
        joint_constraints = [
            JointConstraint(
                joint_name=n,
                position=float(p),
                tolerance_above=tolerance,
                tolerance_below=tolerance,
                weight=1.0,
            )
            for n, p in zip(joints, positions)
        ]
        goal.request.goal_constraints.append(Constraints(joint_constraints=joint_constraints))
        if "planning_scene_diff" in kwargs:
            goal.planning_options.planning_scene_diff = kwargs["planning_scene_diff"]
        return self._send(goal, wait)

    def moveToPose(  # noqa: N802
        self, pose_stamped: Any, gripper_frame: str, tolerance: float = 0.01, wait: bool = True, **kwargs: Any
    ) -> Any:
        _log_unsupported("moveToPose", kwargs, _POSE_ARGS)
        goal = self._goal(kwargs)
        pose = self._listener.transformPose(self._fixed_frame, pose_stamped).pose
        header = Header(frame_id=self._fixed_frame)
        sphere = SolidPrimitive(type=SolidPrimitive.SPHERE, dimensions=[tolerance * tolerance])
        region = BoundingVolume(primitives=[sphere], primitive_poses=[pose])
        position = PositionConstraint(
            header=header, link_name=gripper_frame, constraint_region=region, weight=1.0
        )
        orientation = OrientationConstraint(
            header=header,
            orientation=pose.orientation,
            link_name=gripper_frame,
            absolute_x_axis_tolerance=tolerance,
            absolute_y_axis_tolerance=tolerance,
            absolute_z_axis_tolerance=tolerance,
            weight=1.0,
        )
        constraints = Constraints(position_constraints=[position], orientation_constraints=[orientation])
        goal.request.goal_constraints.append(constraints)
        return self._send(goal, wait)

    def _goal(self, kwargs: dict[str, Any]) -> Any:
        """A MoveGroupGoal with moveit_python's request fields and planning options."""
        goal: Any = MoveGroupGoal()
        request = goal.request
        if "start_state" in kwargs:
            request.start_state = kwargs["start_state"]
        else:
            request.start_state.is_diff = True
        request.planner_id = kwargs.get("planner_id", self.planner_id or "")
        request.group_name = self._group
        request.num_planning_attempts = kwargs.get("num_attempts", 1)
        request.allowed_planning_time = kwargs.get("planning_time", self.planning_time)
        request.max_velocity_scaling_factor = kwargs.get("max_velocity_scaling_factor", 0.0)
        goal.planning_options.planning_scene_diff.is_diff = True
        goal.planning_options.planning_scene_diff.robot_state.is_diff = True
        goal.planning_options.plan_only = kwargs.get("plan_only", self.plan_only)
        return goal

    def _send(self, goal: Any, wait: bool) -> Any:
        self._action.send_goal(goal)
        if not wait:
            return None
        self._action.wait_for_result()
        return self._action.get_result()


def _log_unsupported(method: str, kwargs: dict[str, Any], supported: tuple[str, ...]) -> None:
    for name in kwargs:
        if name not in supported:
            _log.info("%s: unsupported argument: %s", method, name)


def _pose_at(x: float, y: float, z: float) -> Any:
    """A Pose at ``x, y, z``, not turned."""
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = float(x), float(y), float(z)
    pose.orientation.w = 1.0
    return pose


class PlanningSceneInterface:
    """moveit_python.PlanningSceneInterface on the cell's planning scene (see the module doc)."""

    def __init__(self, frame: str, ns: str = "", init_from_service: bool = True):
        self._fixed_frame = frame
        self._colors: dict[str, tuple[float, float, float, float]] = {}

    def addBox(  # noqa: N802 (moveit_python's names)
        self,
        name: str,
        size_x: float,
        size_y: float,
        size_z: float,
        x: float,
        y: float,
        z: float,
        use_service: bool = True,
        frame_id: Optional[str] = None,
    ) -> None:
        box = SolidPrimitive(type=SolidPrimitive.BOX, dimensions=[size_x, size_y, size_z])
        self.addSolidPrimitive(name, box, _pose_at(x, y, z), use_service, frame_id)

    def addCube(  # noqa: N802
        self,
        name: str,
        size: float,
        x: float,
        y: float,
        z: float,
        use_service: bool = True,
        frame_id: Any = None,
    ) -> None:
        self.addBox(name, size, size, size, x, y, z, use_service, frame_id)

    def addSolidPrimitive(  # noqa: N802
        self, name: str, solid: Any, pose: Any, use_service: bool = True, frame_id: Optional[str] = None
    ) -> None:
        """Adds a BOX ``solid`` at ``pose`` in ``frame_id`` (default: the interface's frame)."""
        if solid.type != SolidPrimitive.BOX:
            not_supported(
                f"addSolidPrimitive of shape type {solid.type}",
                "the cell's planning scene holds boxes (type 1)",
            )
        stamped = PoseStamped(header=Header(frame_id=frame_id or self._fixed_frame), pose=pose)
        try:
            scene_of_run().add_box(name, world_pose_of(stamped, "addSolidPrimitive"), list(solid.dimensions))
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def attachBox(  # noqa: N802
        self,
        name: str,
        size_x: float,
        size_y: float,
        size_z: float,
        x: float,
        y: float,
        z: float,
        link_name: str,
        touch_links: Any = None,
        detach_posture: Any = None,
        weight: float = 0.0,
        use_service: bool = True,
    ) -> None:
        """Attaches a box at ``x, y, z`` in ``link_name`` (a gripper's link) to that gripper."""
        stamped = PoseStamped(header=Header(frame_id=link_name), pose=_pose_at(x, y, z))
        try:
            X_WO = world_pose_of(stamped, "attachBox")
            scene_of_run().attach_box(robot_of_link(link_name), name, X_WO, [size_x, size_y, size_z])
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None

    def removeCollisionObject(self, name: str, use_service: bool = True) -> None:  # noqa: N802
        """Removes world box ``name`` (an unknown name changes nothing, as in MoveIt)."""
        if name in scene_of_run().names():
            scene_of_run().remove(name)

    def removeAttachedObject(self, name: str, use_service: bool = True) -> None:  # noqa: N802
        """Detaches box ``name``: MoveIt puts a detached object back into the world, where it is."""
        scene = scene_of_run()
        if name in scene.attached():
            scene.detach(None, name)

    def clear(self) -> None:
        for name in self.getKnownCollisionObjects():
            self.removeCollisionObject(name)
        for name in self.getKnownAttachedObjects():
            self.removeAttachedObject(name)

    def getKnownCollisionObjects(self) -> list[str]:  # noqa: N802
        return list(scene_of_run().names())

    def getKnownAttachedObjects(self) -> list[str]:  # noqa: N802
        return list(scene_of_run().attached())

    def waitForSync(self, max_time: float = 2.0) -> None:  # noqa: N802
        """The scene changes at once: nothing to wait for."""

    def setColor(self, name: str, r: float, g: float, b: float, a: float = 0.9) -> None:  # noqa: N802
        self._colors[name] = (r, g, b, a)

    def sendColors(self) -> None:  # noqa: N802
        """Colours are RViz's: the cell's scene has none to change."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(
            f"moveit_python PlanningSceneInterface.{name}",
            "the cell's planning scene holds boxes: addBox, addCube, addSolidPrimitive (BOX), attachBox",
        )
