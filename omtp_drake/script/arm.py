"""An arm of the scripted cell, MoveIt-commander style: :class:`Arm`, the facade a script uses.

Arms (like MoveIt's ``MoveGroupCommander``): ``go`` to a named
pose or joint values, ``move_to`` a tool pose (inverse kinematics; any tf frame),
``move_linear`` along straight lines (like ``compute_cartesian_path``, with a
guard that stops the move as soon as a condition holds), ``plan`` / ``execute``.
Joint moves are collision-aware (Drake's ``SceneGraphCollisionChecker`` and OMPL's
RRTConnect, :mod:`omtp_drake.control.motion`) and timed within the arm's joint velocity
and acceleration limits (TOPP-RA). A move that touches anything it should not
stops the arm and raises :class:`~omtp_drake.errors.CollisionError` naming what
it hit; a move that cannot be planned raises
:class:`~omtp_drake.errors.PlanningError` before anything moves.

Tool frames: ``tip`` (the suction cup's face, default), ``suction_cup`` (the
course's ``vacuum_gripperN_suction_cup``, 0.0675 m behind the face) and ``tool0``.

The arm's parts live beside it: the system feeding its position servo in
:mod:`omtp_drake.script.arm_commander`, the plans it makes and the step loop
that runs them in :mod:`omtp_drake.script.motion` (:class:`Plan`,
:class:`MoveResult`, :data:`SETTLE_TOLERANCE` and :data:`SETTLE_TIMEOUT` are
importable from here too).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Optional, Union

import numpy as np
from pydrake.math import RigidTransform
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.cell.poses import PoseStamped
from omtp_drake.errors import (
    ConfigError,
    GoalInCollisionError,
    PlanningError,
    UnknownNameError,
    UnreachableError,
    check_duration,
)
from omtp_drake.scenario import RobotConfig
from omtp_drake.script.arm_commander import ArmCommander
from omtp_drake.script.motion import SETTLE_TIMEOUT, SETTLE_TOLERANCE, MoveResult, MoveRunner, MoveSteps, Plan
from omtp_drake.script.scene import CellPlanningScene, world_pose
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.sim.tf import TfBuffer

if TYPE_CHECKING:  # (the planner, OMPL and Drake's planning load when an arm first plans)
    from omtp_drake.control.motion import ArmPlanner
    from omtp_drake.control.motion.scene import CupBox

__all__ = ["SETTLE_TIMEOUT", "SETTLE_TOLERANCE", "Arm", "ArmCommander", "MoveResult", "Plan", "Target"]

Target = Union[str, Sequence[float], np.ndarray, RigidTransform, PoseStamped]


class Arm:
    """One arm of the cell, MoveIt-commander style. Get it from
    :meth:`~omtp_drake.script.cell.Cell.arm`."""

    def __init__(
        self,
        runtime: FactoryRuntime,
        tf: TfBuffer,
        name: str,
        commander: ArmCommander,
        scene: CellPlanningScene,
        steps: MoveSteps,
    ):
        self._runtime = runtime
        self._tf = tf
        self._scene = scene
        self.name = name
        self.config = runtime.station.arm(name).config
        self._planner: Optional[ArmPlanner] = None
        self._tool_frames = arms.tool_frame_names(self.config)
        self._motion = MoveRunner(runtime, name, commander, scene, steps)

    # ------------------------------------------------------------ state

    @property
    def planner(self) -> ArmPlanner:
        """The arm's planner (built on first use, about 0.3 s)."""
        if self._planner is None:
            from omtp_drake.control.motion import ArmPlanner

            self._planner = ArmPlanner(self._runtime.scenario, self.name)
        return self._planner

    def joint_values(self) -> np.ndarray:
        """The measured joint positions (pan, lift, elbow, wrist 1, 2, 3), rad."""
        return self._runtime.joint_positions(self.name)

    def contacts(self) -> list[tuple[str, str]]:
        """What the arm or its gripper touches now, as sorted (own body, other body)
        name pairs: the static cell, the other arm, parts added to the planning scene
        (other parts are pushed, not collided with). The motion commands stop with
        ``CollisionError`` when this is not empty."""
        return self._motion.contacts()

    def tool_pose(self, frame: str = "tip") -> RigidTransform:
        """``X_WE``: where tool frame E (``tip``, ``suction_cup``, ``tool0``) is now."""
        plant = self._runtime.station.plant
        return plant.GetFrameByName(self._frame(frame)).CalcPoseInWorld(
            plant.GetMyContextFromRoot(self._runtime.context)
        )

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The arm's six joints, base to wrist, as the course's URDF names them (unprefixed)."""
        return arms.JOINT_NAMES

    @property
    def velocity_limits(self) -> tuple[float, ...]:
        """The joints' velocity limits (rad/s, :attr:`joint_names`' order): what plans are timed to."""
        return tuple(arms.joint_velocity_limits(self.config).tolist())

    def named_poses(self) -> list[str]:
        """The course's named poses of this arm (``R2Home``...)."""
        return [k for k in arms.NAMED_POSES if k.startswith(self.config.pose_prefix)]

    # ------------------------------------------------------------ planning

    def plan(
        self, target: Target, *, frame: str = "tip", speed: float = 1.0, start: Optional[np.ndarray] = None
    ) -> Plan:
        """A collision-free joint motion from where the arm is (or from ``start``, six
        joint values) to ``target``:
        a named pose (``Home``, ``R2Place``), six joint values, or a tool pose
        (``RigidTransform`` in world, or a :class:`PoseStamped` in any tf frame) for
        tool frame ``frame``. ``speed`` scales the joint velocity limits (0, 1].

        Raises:
            PlanningError: unreachable or outside the joint limits (UnreachableError),
                the goal or the start in collision (GoalInCollisionError,
                StartInCollisionError), or no collision-free path (the message says
                which and names the bodies).
        """
        speed = _check_fraction("speed", speed)
        planner, other_q = self._planning_scene(), other_arm_positions(self._runtime, self.name)
        q_start = self.joint_values() if start is None else np.asarray(start, dtype=float)
        q_goal = self._goal(target, frame, planner, other_q, q_start)
        path = planner.plan(q_start, q_goal, other_q=other_q)
        trajectory = planner.time_parameterize(path, velocity_scale=speed)
        return Plan(trajectory, tuple(path), "joint")

    def compute_cartesian_path(
        self,
        waypoints: RigidTransform | PoseStamped | Sequence[RigidTransform | PoseStamped],
        max_step: float = 0.005,
        jump_threshold: float = 0.5,
        avoid_collisions: bool = True,
        *,
        frame: str = "tip",
        speed: float = 0.25,
        joint_limits: Optional[tuple[Sequence[float], Sequence[float]]] = None,
        start: Optional[np.ndarray] = None,
    ) -> Plan:
        """Straight lines of tool frame ``frame`` through the poses ``waypoints`` (world,
        or PoseStamped in any tf frame), in steps of ``max_step`` m, like MoveIt's
        ``compute_cartesian_path(waypoints, eef_step, jump_threshold, avoid_collisions)``:
        the plan covers the part of the motion reachable without a joint jump over
        ``jump_threshold`` rad (0: no check, as in MoveIt) and, with
        ``avoid_collisions``, without a collision with the planning scene (the static
        cell, the other arm, added boxes, what the gripper holds; loose parts are no
        obstacles). It unpacks as MoveIt's ``(plan, fraction)``; see
        :attr:`Plan.fraction`. ``speed``: the tool's speed limit along the lines (m/s);
        ``joint_limits``: (velocity, acceleration) limits of the six joints to time the
        motion with (default: the arm's own); ``start``: six joint values to start from
        (default: where the arm is)."""
        if isinstance(waypoints, (RigidTransform, PoseStamped)):
            waypoints = [waypoints]
        poses = [world_pose(self._tf, X) for X in waypoints]
        speed = check_duration("speed", speed)  # a positive finite number
        max_step = check_duration("max_step", max_step)  # a positive finite length
        if not (jump_threshold >= 0 and math.isfinite(jump_threshold)):
            raise ConfigError(
                f"jump_threshold must be a finite angle >= 0 rad (0: no check), got {jump_threshold}"
            )
        planner = self._planning_scene()
        path, fraction = planner.cartesian_path(
            self.joint_values() if start is None else np.asarray(start, dtype=float),
            poses,
            frame=frame,
            max_step=max_step,
            jump_threshold=float(jump_threshold) or None,
            avoid_collisions=bool(avoid_collisions),
            other_q=other_arm_positions(self._runtime, self.name),
        )
        velocity, acceleration = joint_limits if joint_limits is not None else (None, None)
        trajectory = planner.time_parameterize(
            path, velocity_scale=1.0, velocity_limits=velocity, acceleration_limits=acceleration
        )
        trajectory = _limit_tool_speed(trajectory, planner, frame, speed)
        return Plan(trajectory, tuple(path), "cartesian", fraction)

    # ------------------------------------------------------------ moves

    def go(self, target: Target, *, frame: str = "tip", speed: float = 1.0) -> MoveResult:
        """Moves to ``target`` (see :meth:`plan`) around obstacles and waits until the
        arm has arrived (every joint within 0.5 mrad)."""
        return self.execute(self.plan(target, frame=frame, speed=speed))

    def move_to(
        self, pose: RigidTransform | PoseStamped, *, frame: str = "tip", speed: float = 1.0
    ) -> MoveResult:
        """Moves tool frame ``frame`` to ``pose`` (a world pose, or a PoseStamped in
        any tf frame) with a collision-free joint motion."""
        if not isinstance(pose, (RigidTransform, PoseStamped)):
            raise ConfigError(f"move_to needs a RigidTransform or PoseStamped, got {type(pose).__name__}")
        return self.go(pose, frame=frame, speed=speed)

    def move_linear(
        self,
        waypoints: RigidTransform | Sequence[RigidTransform],
        *,
        frame: str = "tip",
        speed: float = 0.25,
        until: Optional[Callable[[], bool]] = None,
    ) -> MoveResult:
        """Moves tool frame ``frame`` in straight lines through ``waypoints`` at up to
        ``speed`` m/s. With ``until``, the move stops as soon as ``until()`` is true
        (checked every 10 ms of simulated time), e.g. ``until=lambda: vacuum.attached``.

        Raises:
            PlanningError: part of the motion is not reachable in a straight line
                (the message gives the fraction that is); nothing moves then.
        """
        plan = self.compute_cartesian_path(waypoints, frame=frame, speed=speed)
        if plan.fraction < 1.0 - 1e-9:
            raise PlanningError(
                f"{self.name}: only {100 * plan.fraction:.0f} % of the straight-line motion is "
                "reachable without a collision or a joint jump; nothing moved"
            )
        return self.execute(plan, until=until)

    def execute(
        self, plan: Plan, *, until: Optional[Callable[[], bool]] = None, wait: bool = True
    ) -> MoveResult:
        """Runs ``plan`` from now; returns when it has finished (or ``until()`` held).

        ``wait=False`` (MoveIt's): starts the motion and returns at once; the arm
        moves while the cell runs (``cell.wait``, another arm's move), with no guard
        and no contact check; the result's ``end`` is when the plan ends."""
        if until is not None and not wait:
            raise ConfigError("execute: a guard (until) needs wait=True; valid: until=None with wait=False")
        q_now = self.joint_values()
        q_first = plan.trajectory.value(plan.trajectory.start_time()).ravel()
        if np.max(np.abs(q_first - q_now)) > 0.01:
            raise PlanningError(
                f"{self.name}: the plan starts at {np.round(q_first, 3).tolist()} but the arm is at "
                f"{np.round(q_now, 3).tolist()}; plan again from where it is"
            )
        if not wait:
            start = self._motion.start(plan)
            return MoveResult(start, start + plan.duration, False, q_now)
        return self._motion.run(plan, until)

    def set_joint_values(self, q: Sequence[float] | np.ndarray) -> None:
        """Puts the arm at ``q`` at once and holds it there: a teleport, as Gazebo's
        ``Joint::SetPosition`` (``gazebo_ros_joint_pose_trajectory``), with no motion,
        no plan and no contact check. Raises UnreachableError outside the joint limits."""
        self._motion.teleport(_joint_goal(q, self.config))

    # ------------------------------------------------------------ helpers

    def _frame(self, frame: str) -> str:
        if frame not in self._tool_frames:
            raise UnknownNameError("tool frame", frame, self._tool_frames)
        return self._tool_frames[frame]

    def _planning_scene(self) -> ArmPlanner:
        """The planner with the cell's planning scene (:func:`_scene_planner`)."""
        return _scene_planner(self)

    def _goal(
        self,
        target: Target,
        frame: str,
        planner: ArmPlanner,
        other_q: dict[str, np.ndarray],
        q_start: np.ndarray,
    ) -> np.ndarray:
        """The joint positions of ``target`` (see :meth:`plan`), in ``planner``'s scene
        (IK seeded from ``q_start``)."""
        if isinstance(target, str):
            return arms.named_pose(target, self.config)
        if isinstance(target, (RigidTransform, PoseStamped)):
            X_WE = world_pose(self._tf, target)
            return planner.ik(X_WE, frame=frame, q_seed=q_start, other_q=other_q)
        q = _joint_goal(target, self.config)
        collisions = planner.collisions(q, other_q)
        if collisions:
            pairs = ", ".join(f"{a} - {b}" for a, b in collisions)
            raise GoalInCollisionError(
                f"{self.name}: the goal {np.round(q, 3).tolist()} is in collision: {pairs}"
            )
        return q


def _scene_planner(arm: Arm) -> ArmPlanner:
    """``arm``'s planner with the cell's planning scene (MoveIt's semantics): its boxes
    as obstacles, named; on the gripper, the held part and the boxes attached to
    this arm. Loose parts are not obstacles unless added to the scene."""
    planner = arm.planner
    runtime = arm._runtime
    held = runtime.gripper_state(arm.name) if arm.name in runtime.station.grippers else None
    held_part = held.part if held is not None and held.attached and held.X_CP is not None else ""
    objects = {n: b for n, b in arm._scene.objects().items() if n != held_part}
    planner.scene.set_obstacles([(b.X, b.size) for b in objects.values()], names=list(objects))
    carried: list[CupBox] = [(b.X, b.size, n) for n, b in arm._scene.attached(arm.name).items()]
    if held is not None and held_part and held.X_CP is not None:
        # Shrunk by the planner's margin (and 2 mm) on every side: a part held where it
        # rests (on the floor, on other parts) is not "in collision" with what it rests on.
        size = runtime.scenario.part_size(held_part) - 2 * (planner.margin + 0.002)
        carried.append((held.X_CP, max(size, 0.01), f"{held_part} (held)"))
    if carried:
        planner.scene.set_cup_boxes(carried)
    else:
        planner.scene.clear_held_part()
    return planner


def _joint_goal(target: Sequence[float] | np.ndarray, config: RobotConfig) -> np.ndarray:
    """``target`` as six joint positions of the arm ``config``: ConfigError when they
    are no six finite numbers, UnreachableError when they are outside the joint limits."""
    try:
        return arms.check_joint_positions(target, config)
    except ConfigError as e:
        error = e
    # Six finite numbers pass without limits: the limits were what refused them.
    arms.check_joint_positions(target, replace(config, joint_limit=math.inf, joint_limits=[]))
    raise UnreachableError(f"{config.name}: the goal is outside the joint limits: {error}")


def _check_fraction(what: str, value: float) -> float:
    value = float(value)
    if not 0 < value <= 1:
        raise ConfigError(f"{what} must be in (0, 1], got {value}")
    return value


def _limit_tool_speed(
    trajectory: PiecewisePolynomial, planner: ArmPlanner, frame: str, speed: float
) -> PiecewisePolynomial:
    """``trajectory`` slowed down uniformly (time stretched) so the tool frame's speed
    never exceeds ``speed`` m/s (sampled every 5 ms)."""
    t0, t1 = trajectory.start_time(), trajectory.end_time()
    if t1 - t0 <= 1e-6:
        return trajectory
    times = np.linspace(t0, t1, max(3, int((t1 - t0) / 0.005) + 1))
    points = np.array(
        [planner.forward_kinematics(trajectory.value(t).ravel(), frame).translation() for t in times]
    )
    peak = float(np.max(np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(times)))
    if peak <= speed:
        return trajectory
    scale = peak / speed
    breaks = trajectory.get_segment_times()
    knots = np.column_stack([trajectory.value(t).ravel() for t in breaks])
    slopes = np.column_stack([trajectory.EvalDerivative(t, 1).ravel() / scale for t in breaks])
    new_times = [t0 + (t - t0) * scale for t in breaks]
    return PiecewisePolynomial.CubicHermite(new_times, knots, slopes)


def other_arm_positions(runtime: FactoryRuntime, name: str) -> dict[str, np.ndarray]:
    """The measured positions of the arms other than ``name``, within their joint limits (a
    wrist measured a hair beyond its limit is on it: they only place the other arms' bodies)."""
    return {
        other: np.clip(runtime.joint_positions(other), -handles.config.limits(), handles.config.limits())
        for other, handles in runtime.station.arms.items()
        if other != name
    }
