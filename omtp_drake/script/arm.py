"""An arm of the scripted cell, MoveIt-commander style: plans, moves and the system that commands it.

Arms (:class:`Arm`, like MoveIt's ``MoveGroupCommander``): ``go`` to a named
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

An arm's position servo is fed by its :class:`ArmCommander`, a system the
:class:`~omtp_drake.script.cell.Cell` adds to the diagram.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Optional, Union

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, DiscreteValues, LeafSystem, OutputPort
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.cell.poses import PoseStamped
from omtp_drake.control.motion import ArmPlanner
from omtp_drake.control.motion.scene import CupBox
from omtp_drake.errors import CollisionError, ConfigError, PlanningError, UnknownNameError, check_duration
from omtp_drake.scenario import RobotConfig
from omtp_drake.script.scene import CellPlanningScene, world_pose
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.sim.tf import TfBuffer

#: How often (s) a guarded move checks its condition, and an unguarded one its contacts.
GUARD_PERIOD = 0.01
CONTACT_CHECK_PERIOD = 0.05
#: A joint move has arrived when every joint is this close (rad) to its goal.
SETTLE_TOLERANCE = 5e-4
#: ...and waits at most this long (s) after its trajectory's end for that.
SETTLE_TIMEOUT = 1.0
#: A guarded move that fires stops with this deceleration (m/s^2 at the tool, about).
_STOP_TIME = 0.1

Target = Union[str, Sequence[float], np.ndarray, RigidTransform, PoseStamped]


@dataclass(frozen=True)
class _Command:
    """What an arm is told to do: follow ``trajectory`` (its own time axis, shifted by
    ``t0``), then hold its end; or hold ``q`` when there is none."""

    q: np.ndarray
    trajectory: Optional[PiecewisePolynomial] = None
    t0: float = 0.0

    def __deepcopy__(self, memo: dict) -> _Command:
        return self  # immutable: Drake clones abstract state on every update

    def at(self, t: float) -> np.ndarray:
        if self.trajectory is None:
            return self.q
        tau = min(max(t - self.t0, self.trajectory.start_time()), self.trajectory.end_time())
        return self.trajectory.value(tau).ravel()


class ArmCommander(LeafSystem):
    """Feeds an arm's position servo with a joint trajectory that a script sets.

    .. pydrake_system::

        name: ArmCommander
        output_ports:
        - position

    Output port ``position`` (vector, 6, :meth:`position_output_port`): the
    trajectory sampled at ``rate_hz`` (the servo's command rate) and held, so
    the servo reads a cached value between samples (no Python per plant step).

    State: abstract, the command (:class:`_Command`: a trajectory and its start
    time, or a position to hold); discrete, the sampled position. A script sets a
    new command between advances with :meth:`command`.
    """

    def __init__(self, robot: RobotConfig):
        super().__init__()
        self.set_name(f"{robot.name}.commander")
        q0 = arms.named_pose(robot.initial_pose, robot)
        self._command = self.DeclareAbstractState(AbstractValue.Make(_Command(q0)))
        self._q = self.DeclareDiscreteState(q0)
        self._position_port = self.DeclareStateOutputPort("position", self._q)
        self.DeclarePeriodicDiscreteUpdateEvent(1.0 / robot.command_rate_hz, 0.0, self._sample)
        self.DeclareInitializationDiscreteUpdateEvent(self._sample)

    def position_output_port(self) -> OutputPort:
        """The ``position`` output: the sampled joint positions for the arm's servo."""
        return self._position_port

    def _sample(self, context: Context, discrete_state: DiscreteValues) -> None:
        command: _Command = context.get_abstract_state(self._command).get_value()
        discrete_state.set_value(self._q, command.at(context.get_time()))

    def command(self, context: Context, command: _Command) -> None:
        """The new command, from now on (the sampled position follows at the next sample)."""
        context.SetAbstractState(self._command, command)

    def current(self, context: Context) -> _Command:
        return context.get_abstract_state(self._command).get_value()

    def commanded_position(self, context: Context) -> np.ndarray:
        """The position the servo is being sent now."""
        return context.get_discrete_state(self._q).value().copy()


@dataclass(frozen=True)
class Plan:
    """A timed joint motion of one arm, ready to :meth:`Arm.execute`.

    Attributes:
        trajectory: joint positions over the plan's own time (from 0).
        path: the joint waypoints it was timed through.
        kind: ``joint`` (straight or planned around obstacles), ``cartesian``.
        fraction: for a Cartesian plan, the fraction of the asked motion it covers.
    """

    trajectory: PiecewisePolynomial
    path: tuple[np.ndarray, ...]
    kind: str
    fraction: float = 1.0

    @property
    def duration(self) -> float:
        return self.trajectory.end_time() - self.trajectory.start_time()

    def __iter__(self) -> Iterator[Any]:
        """``plan, fraction = arm.compute_cartesian_path(...)`` unpacks like MoveIt's tuple."""
        return iter((self, self.fraction))


@dataclass(frozen=True)
class MoveResult:
    """What a move did.

    Attributes:
        start, end: simulated times (s).
        stopped: a guard (``until``) stopped the move before its end.
        q: the arm's joint positions when the call returned.
    """

    start: float
    end: float
    stopped: bool
    q: np.ndarray = field(repr=False)


class _ArmMotion:
    """An arm's motions in the running cell: a plan handed to its commander, run
    with its guard and contact checks, and stopped when the guard fires."""

    def __init__(
        self,
        runtime: FactoryRuntime,
        name: str,
        commander: ArmCommander,
        scene: CellPlanningScene,
        step_hooks: list[Callable[[], None]],
    ):
        self._runtime = runtime
        self._commander = commander
        self._scene = scene
        self._step_hooks = step_hooks
        self.name = name

    def _joint_values(self) -> np.ndarray:
        return self._runtime.joint_positions(self.name)

    def contacts(self) -> list[tuple[str, str]]:
        """What the arm or its gripper touches now, as sorted (own body, other body)
        name pairs: the static cell, the other arm, and parts added to the planning
        scene. Other parts are left out: they are pressed and pushed by physics (the
        cup's vacuum attaches one on contact). The motion commands stop with
        ``CollisionError`` when this is not empty."""
        plant = self._runtime.station.plant
        plant_context = plant.GetMyContextFromRoot(self._runtime.context)
        # SceneGraph's penetration query: the pairs the plant's contact results would
        # list, at a fifth of the cost of evaluating those after a step.
        query = plant.get_geometry_query_input_port().Eval(plant_context)
        pairs = query.ComputePointPairPenetration()
        if not pairs:
            return []
        inspector = query.inspector()
        own, parts = self._contact_bodies
        names = self._scene.names()  # parts in it are obstacles, but for the one held
        held = self._held_part() if names else ""
        guarded = {parts[n] for n in names if n in parts and n != held}
        ignored = set(parts.values()) - guarded
        touched = set()
        for pair in pairs:
            a, b = (plant.GetBodyFromFrameId(inspector.GetFrameId(g)) for g in (pair.id_A, pair.id_B))
            for mine, other in ((a, b), (b, a)):
                i, j = int(mine.index()), int(other.index())
                if i in own and j not in own and j not in ignored:
                    touched.add((mine.name(), other.name()))
        return sorted(touched)

    def _held_part(self) -> str:
        """The part this arm's gripper holds ("" when none, or no gripper)."""
        runtime = self._runtime
        return runtime.gripper_state(self.name).part if self.name in runtime.station.grippers else ""

    @functools.cached_property
    def _contact_bodies(self) -> tuple[set[int], dict[str, int]]:
        """Body indices (fixed once the station is built): the arm's and its
        gripper's, and the parts' by name."""
        station = self._runtime.station
        plant = station.plant
        handles = station.arm(self.name)
        own = {int(b) for b in plant.GetBodyIndices(handles.arm)}
        if handles.gripper is not None:
            own |= {int(b) for b in plant.GetBodyIndices(handles.gripper)}
        parts = {n: int(plant.GetBodyByName(n, i).index()) for n, i in station.parts.items()}
        return own, parts

    def start(self, plan: Plan) -> float:
        """Hands ``plan`` to the arm's commander from now; returns the start time."""
        commander = self._commander
        context = commander.GetMyMutableContextFromRoot(self._runtime.context)
        start = self._runtime.time
        # The plan's first sample is where the arm is; the commander takes over from it.
        commander.command(
            context, _Command(q=commander.commanded_position(context), trajectory=plan.trajectory, t0=start)
        )
        return start

    def run(self, plan: Plan, until: Optional[Callable[[], bool]]) -> MoveResult:
        """Runs ``plan`` from now to its end (and until the arm has settled), or
        until ``until()`` holds; checks the arm's contacts on the way."""
        runtime = self._runtime
        commander = self._commander
        context = commander.GetMyMutableContextFromRoot(runtime.context)
        start = self.start(plan)
        end = start + plan.duration
        period = GUARD_PERIOD if until is not None else CONTACT_CHECK_PERIOD
        stopped = False
        next_contact_check = start + CONTACT_CHECK_PERIOD
        while runtime.time < end - 1e-9:
            runtime.advance_to(min(end, runtime.time + period))
            if runtime.time >= next_contact_check - 1e-9 or runtime.time >= end - 1e-9:
                self._check_contacts()
                next_contact_check = runtime.time + CONTACT_CHECK_PERIOD
            self._between_steps()
            if until is not None and until():
                stopped = True
                self._stop(context)
                break
        goal = commander.current(context).at(math.inf)
        settle_end = runtime.time + SETTLE_TIMEOUT
        while (
            not stopped
            and np.max(np.abs(self._joint_values() - goal)) > SETTLE_TOLERANCE
            and runtime.time < settle_end - 1e-9
        ):
            runtime.advance_to(min(settle_end, runtime.time + GUARD_PERIOD))
            self._check_contacts()
            self._between_steps()
        return MoveResult(start, runtime.time, stopped, self._joint_values())

    def _between_steps(self) -> None:
        """The cell's move-step hooks (see :meth:`Cell.on_move_step
        <omtp_drake.script.cell.Cell.on_move_step>`)."""
        for hook in self._step_hooks:
            hook()

    def _stop(self, context: Context) -> None:
        """Decelerates from the commanded motion to rest over about 0.1 s."""
        command = self._commander.current(context)
        t = self._runtime.time
        q = command.at(t)
        if command.trajectory is None:
            return
        tau = min(max(t - command.t0, command.trajectory.start_time()), command.trajectory.end_time())
        v = command.trajectory.EvalDerivative(tau, 1).ravel()
        q_rest = q + 0.5 * v * _STOP_TIME
        stop = PiecewisePolynomial.CubicHermite(
            [0.0, _STOP_TIME], np.column_stack([q, q_rest]), np.column_stack([v, np.zeros_like(v)])
        )
        self._commander.command(context, replace(command, trajectory=stop, t0=t))
        self._runtime.advance(_STOP_TIME)

    def _check_contacts(self) -> None:
        """Raises CollisionError if the arm or its gripper touches anything but a
        loose part (see :meth:`contacts`)."""
        touched = self.contacts()
        if not touched:
            return
        context = self._commander.GetMyMutableContextFromRoot(self._runtime.context)
        self._commander.command(context, _Command(q=self._joint_values()))
        pairs = ", ".join(f"{a} - {b}" for a, b in touched)
        raise CollisionError(
            f"t={self._runtime.time:.2f} s: {self.name} touched something it should not: {pairs}; "
            "it stopped there"
        )


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
        step_hooks: list[Callable[[], None]],
    ):
        self._runtime = runtime
        self._tf = tf
        self._scene = scene
        self.name = name
        self.config = runtime.station.arm(name).config
        self._planner: Optional[ArmPlanner] = None
        self._tool_frames = arms.tool_frame_names(self.config)
        self._motion = _ArmMotion(runtime, name, commander, scene, step_hooks)

    # ------------------------------------------------------------ state

    @property
    def planner(self) -> ArmPlanner:
        """The arm's planner (built on first use, about 0.3 s)."""
        if self._planner is None:
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

    def named_poses(self) -> list[str]:
        """The course's named poses of this arm (``R2Home``...)."""
        return [k for k in arms.NAMED_POSES if k.startswith(self.config.pose_prefix)]

    # ------------------------------------------------------------ planning

    def plan(self, target: Target, *, frame: str = "tip", speed: float = 1.0) -> Plan:
        """A collision-free joint motion from where the arm is to ``target``:
        a named pose (``Home``, ``R2Place``), six joint values, or a tool pose
        (``RigidTransform`` in world, or a :class:`PoseStamped` in any tf frame) for
        tool frame ``frame``. ``speed`` scales the joint velocity limits (0, 1].

        Raises:
            PlanningError: unreachable, outside the joint limits, in collision, or no
                collision-free path (the message says which and names the bodies).
        """
        speed = _check_fraction("speed", speed)
        planner, other_q = self._planning_scene(), self._other_arms()
        q_goal = self._goal(target, frame, planner, other_q)
        path = planner.plan(self.joint_values(), q_goal, other_q=other_q)
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
        motion with (default: the arm's own)."""
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
            self.joint_values(),
            poses,
            frame=frame,
            max_step=max_step,
            jump_threshold=float(jump_threshold) or None,
            avoid_collisions=bool(avoid_collisions),
            other_q=self._other_arms(),
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

    # ------------------------------------------------------------ helpers

    def _frame(self, frame: str) -> str:
        if frame not in self._tool_frames:
            raise UnknownNameError("tool frame", frame, self._tool_frames)
        return self._tool_frames[frame]

    def _goal(
        self, target: Target, frame: str, planner: ArmPlanner, other_q: dict[str, np.ndarray]
    ) -> np.ndarray:
        """The joint positions of ``target`` (see :meth:`plan`), in ``planner``'s scene."""
        if isinstance(target, str):
            return arms.named_pose(target, self.config)
        if isinstance(target, (RigidTransform, PoseStamped)):
            X_WE = world_pose(self._tf, target)
            return planner.ik(X_WE, frame=frame, q_seed=self.joint_values(), other_q=other_q)
        try:
            q = arms.check_joint_positions(target, self.config)
        except ConfigError as e:
            if "outside its limits" not in str(e):
                raise
            raise PlanningError(f"{self.name}: the goal is outside the joint limits: {e}") from None
        collisions = planner.collisions(q, other_q)
        if collisions:
            pairs = ", ".join(f"{a} - {b}" for a, b in collisions)
            raise PlanningError(f"{self.name}: the goal {np.round(q, 3).tolist()} is in collision: {pairs}")
        return q

    def _other_arms(self) -> dict[str, np.ndarray]:
        return {
            name: self._runtime.joint_positions(name)
            for name in self._runtime.station.arms
            if name != self.name
        }

    def _planning_scene(self) -> ArmPlanner:
        """The planner with the cell's planning scene (MoveIt's semantics): its boxes
        as obstacles, named; on the gripper, the held part and the boxes attached to
        this arm. Loose parts are not obstacles unless added to the scene."""
        planner = self.planner
        runtime = self._runtime
        held = runtime.gripper_state(self.name) if self.name in runtime.station.grippers else None
        held_part = held.part if held is not None and held.attached and held.X_CP is not None else ""
        objects = {n: b for n, b in self._scene.objects().items() if n != held_part}
        planner.scene.set_obstacles([(b.X, b.size) for b in objects.values()], names=list(objects))
        carried: list[CupBox] = [(b.X, b.size, n) for n, b in self._scene.attached(self.name).items()]
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
