"""What a moveit_commander MoveGroupCommander's next plan aims for, and how.

:class:`MoveGroupTargets`, the commander's half that sets its goal: named
targets (the group's SRDF states and the remembered joint values), joint-value
and pose targets, and the plan options (velocity and acceleration scaling
factors; planning time, attempts, planner, tolerances are logged and left to the
cell's planner). :class:`~omtp_drake.ros.moveit.commander.MoveGroupCommander` plans and
moves to the target set here. A bad argument raises
:class:`MoveItCommanderException`, as in MoveIt.
"""

from __future__ import annotations

import logging
from typing import Any, Optional

import numpy as np

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm._core import Arm, CorePoseStamped, check_joint_positions
from omtp_drake.ros.comm.messages import JointState, Pose, PoseStamped
from omtp_drake.ros.comm.unsupported import not_supported
from omtp_drake.ros.moveit.bounds import JointBounds, target_within
from omtp_drake.ros.moveit.srdf import SemanticModel
from omtp_drake.ros.moveit.trajectories import joint_names
from omtp_drake.ros.tf.convert import pose_from_list, rigid

_log = logging.getLogger("moveit_commander")


class MoveItCommanderException(Exception):
    """A bad argument to a commander (unknown group, name, link, or a target out of bounds)."""


class MoveGroupTargets:
    """The target and plan options of a move group's commander (see the module doc).

    The commander sets the group's name, robot, arm, semantics, end-effector
    links and the options' defaults; the target is ``("joints", q)`` or
    ``("pose", (pose, tool frame))``, or None when none is set.
    """

    _name: str
    _robot: str
    _arm: Arm
    _semantic: SemanticModel
    _links: dict[str, str]
    _eef: str
    _target: Optional[tuple[str, Any]]
    _remembered: dict[str, np.ndarray]
    _velocity_scale: float
    _acceleration_scale: float

    def _bounds(self) -> JointBounds:
        """The group's joints and their position bounds."""
        limits = self._arm.config.limits()
        return JointBounds(tuple(joint_names(self._robot)), -limits, limits)

    def _short(self, link: str) -> str:
        link = link or self._eef
        if link not in self._links:
            raise MoveItCommanderException(
                f"{link!r} is no link of {self._name}; links: {', '.join(self._links)}"
            )
        return self._links[link]

    def get_named_targets(self) -> list[str]:
        return list(self._semantic.named_states(self._name)) + sorted(self._remembered)

    def get_named_target_values(self, target: str) -> dict[str, float]:
        """The named state's joint values (the joints its SRDF entry sets)."""
        if target in self._remembered:
            return dict(zip(joint_names(self._robot), map(float, self._remembered[target])))
        states = self._semantic.named_states(self._name)
        if target not in states:
            return {}  # as MoveIt
        return dict(states[target])

    def _named(self, name: str) -> np.ndarray:
        if name in self._remembered:
            return self._remembered[name]
        states = self._semantic.named_states(self._name)
        if name not in states:
            raise MoveItCommanderException(
                f"unable to set target {name!r}: named targets of {self._name}: "
                + ", ".join(self.get_named_targets())
            )
        return self._joints(states[name])

    def set_named_target(self, name: str) -> None:
        self._target = ("joints", self._named(name))

    def remember_joint_values(self, name: str, values: Any = None) -> None:
        q = self._joints(self._arm.joint_values() if values is None else values)
        self._remembered[name] = q

    def get_remembered_joint_values(self) -> dict[str, list[float]]:
        return {k: [float(x) for x in v] for k, v in self._remembered.items()}

    def forget_joint_values(self, name: str) -> None:
        self._remembered.pop(name, None)

    def _joints(self, values: Any) -> np.ndarray:
        if isinstance(values, JointState):
            values = dict(zip(values.name, values.position)) if values.name else list(values.position)
        if isinstance(values, dict):
            names = joint_names(self._robot)
            unknown = sorted(set(values) - set(names))
            if unknown:
                raise MoveItCommanderException(
                    f"{unknown[0]!r} is no joint of {self._name}; joints: {', '.join(names)}"
                )
            current_q = self._arm.joint_values()
            values = [values.get(n, current_q[i]) for i, n in enumerate(names)]
        try:
            values = target_within(self._bounds(), values)
        except (TypeError, ValueError):
            pass  # no numbers: the check below says what is wrong
        try:
            return check_joint_positions(values, self._arm.config)
        except OmtpError as e:
            raise MoveItCommanderException(f"error setting joint target: {e}") from None

    def set_joint_value_target(self, arg1: Any, arg2: Any = None, arg3: Any = None) -> None:
        if isinstance(arg1, str) and arg2 is not None:
            arg1 = {arg1: arg2}
        if isinstance(arg1, (Pose, PoseStamped)):
            not_supported("set_joint_value_target with a pose (approximate IK)", "use set_pose_target")
        self._target = ("joints", self._joints(arg1))

    def set_pose_target(self, pose: Any, end_effector_link: str = "") -> None:
        """A pose target for the end-effector link: a Pose (world), a PoseStamped (any tf
        frame, at its stamp), or a list of 6 (xyz rpy) or 7 (xyz quaternion) numbers.
        Another type, or a pose that is no pose (not finite, a zero quaternion...),
        raises MoveItCommanderException."""
        frame = self._short(end_effector_link)
        try:
            target = _pose_target(pose)
        except OmtpError as e:
            raise MoveItCommanderException(str(e)) from None
        self._target = ("pose", (target, frame))

    def set_pose_targets(self, poses: Any, end_effector_link: str = "") -> None:
        not_supported("MoveGroupCommander.set_pose_targets (several goal poses)", "use set_pose_target")

    def clear_pose_targets(self) -> None:
        self._target = None

    def clear_pose_target(self, end_effector_link: str) -> None:
        self._target = None

    def set_max_velocity_scaling_factor(self, value: float) -> None:
        self._velocity_scale = _fraction("max velocity scaling factor", value)

    def set_max_acceleration_scaling_factor(self, value: float) -> None:
        self._acceleration_scale = _fraction("max acceleration scaling factor", value)

    def set_planning_time(self, seconds: float) -> None:
        _log.info("set_planning_time(%s): the cell's planner has its own time limit", seconds)

    def set_num_planning_attempts(self, num: int) -> None:
        _log.info("set_num_planning_attempts(%s): the cell's planner is deterministic; one attempt", num)

    def set_planner_id(self, planner_id: str) -> None:
        _log.info("set_planner_id(%s): the cell plans with OMPL's RRTConnect", planner_id)

    def allow_replanning(self, value: bool) -> None:
        _log.info("allow_replanning(%s): the cell does not replan", value)

    def set_goal_tolerance(self, value: float) -> None:
        _log.info("set_goal_tolerance(%s): the cell's goals are exact (IK within 0.1 mm)", value)

    set_goal_joint_tolerance = set_goal_position_tolerance = set_goal_orientation_tolerance = (
        set_goal_tolerance
    )


def _pose_target(pose: Any) -> Any:
    """``pose`` (see ``set_pose_target``) as the cell's arms take it: a world pose, or a
    pose stamped in another tf frame. ConfigError when it is no pose."""
    if isinstance(pose, PoseStamped):
        stamp = pose.header.stamp.to_sec()
        target = CorePoseStamped(
            pose.header.frame_id.lstrip("/") or "world",
            stamp or None,
            rigid(pose.pose, "set_pose_target"),
        )
        return target.pose if target.frame_id == "world" else target
    if isinstance(pose, Pose):
        return rigid(pose, "set_pose_target")
    if isinstance(pose, (list, tuple, np.ndarray)):
        return pose_from_list(pose, "set_pose_target")
    raise MoveItCommanderException(
        f"set_pose_target takes a Pose, PoseStamped or list, got {type(pose).__name__}"
    )


def _fraction(what: str, value: float) -> float:
    value = float(value)
    if not 0 < value <= 1:
        raise MoveItCommanderException(f"{what} must be in (0, 1], got {value}")
    return value
