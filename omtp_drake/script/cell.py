"""Script the cell yourself: arms, gripper, cameras and tf from a plain script or notebook.

The course's central exercise is a pick script of your own: move the robot to a
named pose, read the logical camera, transform the part's pose with tf, move above
the part with the tool down, switch the vacuum on, move down until the part is
attached, lift, move to the place pose and let go. In ROS that is MoveIt commander,
the gripper service and a tf2 buffer; here it is a :class:`Cell`::

    from omtp_drake import Cell, tool_down

    with Cell("lecture6_assignment4", auto_spawn=False) as cell:
        arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
        arm.go("Home")
        part = cell.spawn_part()
        cell.wait(1.5)                                     # it falls and settles
        seen = cell.camera("logical_camera_2").image().pose_of(part)
        p = cell.tf.transform(seen, "world").pose.translation()
        arm.move_to(tool_down(p + [0, 0, 0.2]))            # cup face 0.1 above the top face
        vacuum.on()
        arm.move_linear(tool_down(p + [0, 0, 0.08]), speed=0.05, until=lambda: vacuum.attached)
        arm.go("Home")
        arm.go("Place")
        vacuum.off()

Every call blocks while the simulation advances (simulated time, deterministic)
and returns when its motion has finished; with ``meshcat`` or ``record`` every
motion is shown, or recorded into a replay.

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
"""

from __future__ import annotations

import functools
import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Optional, Union

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context, DiagramBuilder, DiscreteValues, LeafSystem
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.poses import PoseStamped
from omtp_drake.cell.station import Station
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.motion import ArmPlanner
from omtp_drake.errors import (
    CollisionError,
    ConfigError,
    PlanningError,
    SimulationError,
    UnknownNameError,
    check_duration,
)
from omtp_drake.scenario import RobotConfig, Scenario, load_scenario
from omtp_drake.sim.ledger import Ledger
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.sim.tf import TfBuffer
from omtp_drake.viz.meshcat import add_visual_extras, save_recording, start_meshcat, start_recording, view_for

_log = logging.getLogger(__name__)

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


# ----------------------------------------------------------------------------- the command source


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

    Output port ``position`` (vector, 6): the trajectory sampled at
    ``rate_hz`` (the servo's command rate) and held, so the servo reads a
    cached value between samples (no Python per plant step).

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
        self.DeclareStateOutputPort("position", self._q)
        self.DeclarePeriodicDiscreteUpdateEvent(1.0 / robot.command_rate_hz, 0.0, self._sample)
        self.DeclareInitializationDiscreteUpdateEvent(self._sample)

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


# ----------------------------------------------------------------------------- results


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


# ----------------------------------------------------------------------------- the handles


class Arm:
    """One arm of the cell, MoveIt-commander style. Get it from :meth:`Cell.arm`."""

    def __init__(self, cell: Cell, name: str, commander: ArmCommander):
        self._cell = cell
        self._commander = commander
        self.name = name
        self.config = cell.station.arm(name).config
        self._planner: Optional[ArmPlanner] = None
        self._tool_frames = arms.tool_frame_names(self.config)

    # ------------------------------------------------------------ state

    @property
    def planner(self) -> ArmPlanner:
        """The arm's planner (built on first use, about 0.3 s)."""
        if self._planner is None:
            self._planner = ArmPlanner(self._cell.scenario, self.name)
        return self._planner

    def joint_values(self) -> np.ndarray:
        """The measured joint positions (pan, lift, elbow, wrist 1, 2, 3), rad."""
        return self._cell.runtime.joint_positions(self.name)

    def contacts(self) -> list[tuple[str, str]]:
        """What the arm or its gripper touches now, as sorted (own body, other body)
        name pairs; a part in contact with the suction cup is expected and left out.
        The motion commands stop with ``CollisionError`` when this is not empty."""
        plant = self._cell.station.plant
        plant_context = plant.GetMyContextFromRoot(self._cell.runtime.context)
        # SceneGraph's penetration query: the pairs the plant's contact results would
        # list, at a fifth of the cost of evaluating those after a step.
        query = plant.get_geometry_query_input_port().Eval(plant_context)
        pairs = query.ComputePointPairPenetration()
        if not pairs:
            return []
        inspector = query.inspector()
        own, cup, parts = self._contact_bodies
        touched = set()
        for pair in pairs:
            a, b = (plant.GetBodyFromFrameId(inspector.GetFrameId(g)) for g in (pair.id_A, pair.id_B))
            for mine, other in ((a, b), (b, a)):
                i, j = int(mine.index()), int(other.index())
                if i in own and j not in own and not (i == cup and j in parts):
                    touched.add((mine.name(), other.name()))
        return sorted(touched)

    @functools.cached_property
    def _contact_bodies(self) -> tuple[set[int], int, set[int]]:
        """Body indices (fixed once the station is built): the arm's and its
        gripper's, the cup's (-1 without a gripper), the parts'."""
        station = self._cell.station
        plant = station.plant
        handles = station.arm(self.name)
        own = {int(b) for b in plant.GetBodyIndices(handles.arm)}
        if handles.gripper is not None:
            own |= {int(b) for b in plant.GetBodyIndices(handles.gripper)}
        gripper = handles.config.gripper
        cup = int(plant.GetBodyByName(f"{gripper}_cup").index()) if gripper else -1
        parts = {int(plant.GetBodyByName(n, i).index()) for n, i in station.parts.items()}
        return own, cup, parts

    def tool_pose(self, frame: str = "tip") -> RigidTransform:
        """``X_WE``: where tool frame E (``tip``, ``suction_cup``, ``tool0``) is now."""
        plant = self._cell.station.plant
        return plant.GetFrameByName(self._frame(frame)).CalcPoseInWorld(
            plant.GetMyContextFromRoot(self._cell.runtime.context)
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
        waypoints: RigidTransform | Sequence[RigidTransform],
        *,
        frame: str = "tip",
        speed: float = 0.25,
        max_step: float = 0.005,
        avoid_parts: bool = True,
    ) -> Plan:
        """Straight lines of tool frame ``frame`` through world poses ``waypoints``
        (like MoveIt's ``compute_cartesian_path``): the plan covers the part of the
        motion that is reachable without collisions or joint jumps; see
        :attr:`Plan.fraction`. ``speed``: the tool's speed limit along the lines (m/s).
        ``avoid_parts=False``: loose parts are no obstacles (a move meant to touch one)."""
        if isinstance(waypoints, RigidTransform):
            waypoints = [waypoints]
        poses = [self._cell.world_pose(X) for X in waypoints]
        speed = check_duration("speed", speed)  # a positive finite number
        planner = self._planning_scene(avoid_parts=avoid_parts)
        path, fraction = planner.cartesian_path(
            self.joint_values(), poses, frame=frame, max_step=max_step, other_q=self._other_arms()
        )
        trajectory = planner.time_parameterize(path, velocity_scale=1.0)
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
        # A guarded move is meant to touch something (e.g. the part to pick).
        plan = self.compute_cartesian_path(waypoints, frame=frame, speed=speed, avoid_parts=until is None)
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
            start = self._cell._start(self, plan)
            return MoveResult(start, start + plan.duration, False, q_now)
        return self._cell._execute(self, plan, until)

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
            X_WE = self._cell.world_pose(target)
            return planner.ik(X_WE, frame=frame, q_seed=self.joint_values(), other_q=other_q)
        q = arms.check_joint_positions(target, self.config)
        collisions = planner.collisions(q, other_q)
        if collisions:
            pairs = ", ".join(f"{a} - {b}" for a, b in collisions)
            raise PlanningError(f"{self.name}: the goal {np.round(q, 3).tolist()} is in collision: {pairs}")
        return q

    def _other_arms(self) -> dict[str, np.ndarray]:
        return {
            name: self._cell.runtime.joint_positions(name)
            for name in self._cell.station.arms
            if name != self.name
        }

    def _planning_scene(self, avoid_parts: bool = True) -> ArmPlanner:
        """The planner with the cell's loose parts as obstacles (``avoid_parts``) and
        the held part attached."""
        planner = self.planner
        held = self._cell.gripper(self.name).state() if self.name in self._cell.station.grippers else None
        obstacles = []
        for part in self._cell.runtime.parts_in_world() if avoid_parts else []:
            if held is not None and held.attached and part == held.part:
                continue
            size = self._cell.scenario.part_size(part)
            obstacles.append((self._cell.runtime.part_pose(part), size))
        planner.set_obstacles(obstacles)
        if held is not None and held.attached and held.X_CP is not None:
            # Shrunk by the planner's margin (and 2 mm) on every side: a part held where it
            # rests (on the floor, on other parts) is not "in collision" with what it rests on.
            size = self._cell.scenario.part_size(held.part) - 2 * (planner.margin + 0.002)
            planner.set_held_part(held.X_CP, max(size, 0.01))
        else:
            planner.clear_held_part()
        return planner


class Gripper:
    """A vacuum gripper (the course's ``/gripperN/control`` service). Get it from
    :meth:`Cell.gripper`."""

    def __init__(self, cell: Cell, robot: str):
        self._cell = cell
        self.robot = robot

    def on(self) -> None:
        """Vacuum on: a part touching the cup is attached at the next checks (20 Hz)."""
        self._cell.runtime.enable_gripper(self.robot)

    def off(self) -> None:
        """Vacuum off: a held part is released at the next check and falls."""
        self._cell.runtime.disable_gripper(self.robot)

    def state(self) -> GripperState:
        return self._cell.runtime.gripper_state(self.robot)

    @property
    def attached(self) -> bool:
        """A part is held."""
        return self.state().attached

    @property
    def part(self) -> str:
        """The held part's name ("" when none)."""
        return self.state().part

    def wait_for_attach(self, timeout: float = 1.0) -> str:
        """Waits until a part is attached; returns its name (SimulationError after ``timeout`` s)."""
        self._cell.wait_until(lambda: self.attached, timeout, what=f"{self.robot}'s gripper to attach")
        return self.part


class Camera:
    """A logical camera. Get it from :meth:`Cell.camera`."""

    def __init__(self, cell: Cell, name: str):
        self._cell = cell
        self.name = name

    def image(self) -> LogicalCameraImage:
        """The latest image, stamped with the time it was taken."""
        return self._cell.runtime.camera_image(self.name)

    def parts(self, type: str = "object") -> dict[str, PoseStamped]:
        """Name -> pose (in this camera's frame, at the image's time) of every model of
        ``type`` the latest image reports."""
        image = self.image()
        return {m.name: image.pose_of(m.name) for m in image.models if m.type == type and m.name}


# ----------------------------------------------------------------------------- the cell


class Cell:
    """A scenario's cell to script: arms, grippers, cameras, tf, parts, belt, beam.

    Args:
        scenario: a scenario name, path or :class:`Scenario`.
        auto_spawn: let the scenario's spawner spawn parts by itself (False: your
            own :meth:`spawn_part` calls, from t = 0).
        meshcat: serve a live Meshcat view (its URL is logged and in :attr:`url`).
        record: write a standalone HTML replay there at :meth:`close`.
        realtime: pace the simulation at real time (for watching it live).
        tf_cache: how long (s) the tf buffer keeps its history.

    Use it as a context manager (``with Cell(...) as cell:``) so the replay is
    written at the end, or call :meth:`close`.
    """

    def __init__(
        self,
        scenario: Scenario | str,
        *,
        auto_spawn: bool = True,
        meshcat: bool = False,
        record: Optional[str | Path] = None,
        realtime: bool = False,
        tf_cache: float = 30.0,
    ):
        if not isinstance(scenario, Scenario):
            scenario = load_scenario(scenario)
        self.scenario = scenario
        self._record = Path(record) if record else None
        self.meshcat = start_meshcat(view_for(scenario)) if (meshcat or record) else None
        commanders: dict[str, ArmCommander] = {}

        def add_commanders(builder: DiagramBuilder, station: Station) -> None:
            for name, handles in station.arms.items():
                commanders[name] = builder.AddSystem(ArmCommander(handles.config))
                builder.Connect(
                    commanders[name].get_output_port(), station.diagram.GetInputPort(f"{name}.position")
                )

        self.runtime = FactoryRuntime(
            scenario, meshcat=self.meshcat, extend=add_commanders, auto_spawn=auto_spawn
        )
        self.station = self.runtime.station
        if self._record is not None:
            start_recording(self.station.visualizer)
        if self.meshcat is not None:
            add_visual_extras(self.runtime, recording=self._record is not None)
        if realtime:
            self.runtime.simulator.set_target_realtime_rate(1.0)
        self.tf = TfBuffer(self.station, cache_time=tf_cache)
        self.tf.record(self.runtime.context)
        self.runtime.on_tick(lambda rt: self.tf.record(rt.context))
        self._arms = {name: Arm(self, name, c) for name, c in commanders.items()}
        self._closed = False

    # ------------------------------------------------------------ handles

    @property
    def url(self) -> Optional[str]:
        """The live Meshcat view's address (None without one)."""
        return self.meshcat.web_url() if self.meshcat is not None else None

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self.runtime.time

    def arm(self, name: str) -> Arm:
        if name not in self._arms:
            raise UnknownNameError("robot", name, self._arms)
        return self._arms[name]

    def gripper(self, robot: str) -> Gripper:
        self.station.suction_name(robot)  # the error lists the robots with grippers
        return Gripper(self, robot)

    def camera(self, name: str) -> Camera:
        self.runtime.camera_image(name)  # the error lists the cameras
        return Camera(self, name)

    # ------------------------------------------------------------ time

    def wait(self, seconds: float) -> None:
        """Lets the cell run for ``seconds`` of simulated time."""
        self.runtime.advance(check_duration("wait", seconds))

    def wait_until(
        self,
        condition: Callable[[], bool],
        timeout: float,
        *,
        period: float = 0.05,
        what: str = "the condition",
    ) -> None:
        """Runs until ``condition()`` is true (checked every ``period`` s); raises
        SimulationError after ``timeout`` s."""
        timeout = check_duration("timeout", timeout)
        period = check_duration("period", period)
        end = self.time + timeout
        while not condition():
            if self.time >= end - 1e-9:
                raise SimulationError(
                    f"t={self.time:.2f} s: waited {timeout:g} s for {what}; it did not happen"
                )
            self.runtime.advance_to(min(end, self.time + period))

    # ------------------------------------------------------------ world

    def spawn_part(self, xyz: Optional[Sequence[float]] = None, yaw: Optional[float] = None) -> str:
        """Spawns a part (at the scenario's spawn pose unless ``xyz``/``yaw``); returns its name."""
        return self.runtime.spawn_part(xyz, yaw)

    def remove_part(self, name: str) -> None:
        self.runtime.remove_part(name)

    def part_pose(self, name: str) -> RigidTransform:
        """Ground truth, for checking a script (a robot would use a camera)."""
        return self.runtime.part_pose(name)

    def set_conveyor_power(self, power: float) -> None:
        self.runtime.set_conveyor_power(power)

    def conveyor_power(self) -> float:
        return self.runtime.conveyor_power()

    def break_beam(self) -> bool:
        """Is something breaking the beam (as last sampled, 10 Hz)?"""
        return self.runtime.break_beam()[0]

    def ledger(self) -> Ledger:
        return self.runtime.ledger()

    def world_pose(self, pose: RigidTransform | PoseStamped) -> RigidTransform:
        """A pose in world: a RigidTransform is one already; a PoseStamped is transformed
        with tf at its time."""
        if isinstance(pose, PoseStamped):
            return self.tf.transform_pose(pose, "world").pose
        if isinstance(pose, RigidTransform):
            return pose
        raise ConfigError(f"a pose is a RigidTransform (world) or a PoseStamped, got {type(pose).__name__}")

    # ------------------------------------------------------------ execution

    def _start(self, arm: Arm, plan: Plan) -> float:
        """Hands ``plan`` to the arm's commander from now; returns the start time."""
        commander = arm._commander
        context = commander.GetMyMutableContextFromRoot(self.runtime.context)
        start = self.time
        # The plan's first sample is where the arm is; the commander takes over from it.
        commander.command(
            context, _Command(q=commander.commanded_position(context), trajectory=plan.trajectory, t0=start)
        )
        return start

    def _execute(self, arm: Arm, plan: Plan, until: Optional[Callable[[], bool]]) -> MoveResult:
        runtime = self.runtime
        commander = arm._commander
        context = commander.GetMyMutableContextFromRoot(runtime.context)
        start = self._start(arm, plan)
        end = start + plan.duration
        period = GUARD_PERIOD if until is not None else CONTACT_CHECK_PERIOD
        stopped = False
        next_contact_check = start + CONTACT_CHECK_PERIOD
        while self.time < end - 1e-9:
            runtime.advance_to(min(end, self.time + period))
            if self.time >= next_contact_check - 1e-9 or self.time >= end - 1e-9:
                self._check_contacts(arm)
                next_contact_check = self.time + CONTACT_CHECK_PERIOD
            if until is not None and until():
                stopped = True
                self._stop(arm, context)
                break
        goal = commander.current(context).at(math.inf)
        settle_end = self.time + SETTLE_TIMEOUT
        while (
            not stopped
            and np.max(np.abs(arm.joint_values() - goal)) > SETTLE_TOLERANCE
            and self.time < settle_end - 1e-9
        ):
            runtime.advance_to(min(settle_end, self.time + GUARD_PERIOD))
            self._check_contacts(arm)
        return MoveResult(start, self.time, stopped, arm.joint_values())

    def _stop(self, arm: Arm, context: Context) -> None:
        """Decelerates from the commanded motion to rest over about 0.1 s."""
        command = arm._commander.current(context)
        t = self.time
        q = command.at(t)
        if command.trajectory is None:
            return
        tau = min(max(t - command.t0, command.trajectory.start_time()), command.trajectory.end_time())
        v = command.trajectory.EvalDerivative(tau, 1).ravel()
        q_rest = q + 0.5 * v * _STOP_TIME
        stop = PiecewisePolynomial.CubicHermite(
            [0.0, _STOP_TIME], np.column_stack([q, q_rest]), np.column_stack([v, np.zeros_like(v)])
        )
        arm._commander.command(context, replace(command, trajectory=stop, t0=t))
        self.runtime.advance(_STOP_TIME)

    def _check_contacts(self, arm: Arm) -> None:
        """Raises CollisionError if the arm (or its gripper, but for its cup) touches
        anything (a part under the cup and a held part are expected)."""
        touched = arm.contacts()
        if not touched:
            return
        context = arm._commander.GetMyMutableContextFromRoot(self.runtime.context)
        arm._commander.command(context, _Command(q=arm.joint_values()))
        pairs = ", ".join(f"{a} - {b}" for a, b in touched)
        raise CollisionError(
            f"t={self.time:.2f} s: {arm.name} touched something it should not: {pairs}; it stopped there"
        )

    # ------------------------------------------------------------ the end

    def close(self) -> Optional[Path]:
        """Writes the replay (with ``record``); returns its path."""
        if self._closed:
            return None
        self._closed = True
        if self._record is not None and self.meshcat is not None:
            return save_recording(self.station.visualizer, self.meshcat, self._record)
        return None

    def __enter__(self) -> Cell:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


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
