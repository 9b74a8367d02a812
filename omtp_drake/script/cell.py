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
        p = cell.tf.transform_pose(seen, "world").pose.translation()
        arm.move_to(tool_down(p + [0, 0, 0.2]))            # cup face 0.1 above the top face
        vacuum.on()
        arm.move_linear(tool_down(p + [0, 0, 0.08]), speed=0.05, until=lambda: vacuum.attached)
        arm.go("Home")
        arm.go("Place")
        vacuum.off()

Every call blocks while the simulation advances (simulated time, deterministic)
and returns when its motion has finished; with ``meshcat`` or ``record`` every
motion is shown, or recorded into a replay.

The handles it gives out live beside it: arms in :mod:`omtp_drake.script.arm`,
grippers and cameras in :mod:`omtp_drake.script.devices`, bins in
:mod:`omtp_drake.script.bins`, the planning scene (what plans avoid: the static
cell, the other arm, the held part and boxes you add; loose parts are pushed, not
avoided, as in MoveIt) in :mod:`omtp_drake.script.scene`.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Optional

from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder

from omtp_drake.cell.poses import PoseStamped
from omtp_drake.cell.station import Station
from omtp_drake.errors import ConfigError, NotSupportedError, UnknownNameError, check_duration
from omtp_drake.launch.options import cell_of
from omtp_drake.scenario import Scenario
from omtp_drake.scenario.robot_world import RobotSpawn
from omtp_drake.script.arm import Arm
from omtp_drake.script.arm_commander import ArmCommander
from omtp_drake.script.bins import Bin
from omtp_drake.script.devices import Camera, Gripper, wait_until
from omtp_drake.script.motion import MoveSteps
from omtp_drake.script.scene import CellPlanningScene, world_pose
from omtp_drake.sim.faults import FaultReport
from omtp_drake.sim.ledger import Ledger
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.sim.tf import TfBuffer
from omtp_drake.viz.meshcat import add_visual_extras, save_recording, start_meshcat, start_recording, view_for

_log = logging.getLogger("omtp_drake")


class Cell:
    """A scenario's cell to script: arms, grippers, cameras, tf, parts, belt, beam.

    Args:
        scenario: a scenario name, path or :class:`Scenario`; or instead:
        launch: a student's launch file, as roslaunch takes it (``'omtp_lecture6
            lecture6_assignment1.launch paused:=false'``), or
        world: a student's Gazebo world file (None of the three with ``robot``:
            Gazebo's empty world).
        robot: a URDF, xacro or SDF file: the robot spawned into that cell, as
            ``spawn_model`` does (its joints, sensors and gazebo_ros plugins; ``arm``,
            ``gripper`` and MoveIt stay the scenario's UR arms').
        workspace: the folders (catkin ``src``, packages) where the launch, world or
            robot file finds its packages and models (:mod:`omtp_drake.workspace`).
        auto_spawn: let the scenario's spawner spawn parts by itself (False: your
            own :meth:`spawn_part` calls, from t = 0).
        meshcat: serve a live Meshcat view (its URL is logged and in :attr:`url`).
        record: write a standalone HTML replay there at :meth:`close`.
        realtime: pace the simulation at real time (for watching it live).
        tf_cache: how long (s) the tf buffer keeps its history.

    Use it as a context manager (``with Cell(...) as cell:``) or call :meth:`close`:
    closing writes the replay and frees the cell (its diagram, plant and Contexts;
    an unclosed cell stays in memory for the life of the process). A closed cell
    refuses to run: build a new one.
    """

    def __init__(
        self,
        scenario: Scenario | str | None = None,
        *,
        launch: Optional[str] = None,
        world: Optional[str | Path] = None,
        robot: Optional[str | Path] = None,
        workspace: Sequence[str | Path] | str | Path = (),
        auto_spawn: bool = True,
        meshcat: bool = False,
        record: Optional[str | Path] = None,
        realtime: bool = False,
        tf_cache: float = 30.0,
    ):
        scenario = _cell_scenario(scenario, launch, world, robot, workspace)
        self.scenario = scenario
        self._record = Path(record) if record else None
        self.meshcat = start_meshcat(view_for(scenario)) if (meshcat or record) else None
        commanders: dict[str, ArmCommander] = {}

        def add_commanders(builder: DiagramBuilder, station: Station) -> None:
            for name, handles in station.arms.items():
                commanders[name] = builder.AddSystem(ArmCommander(handles.config))
                builder.Connect(
                    commanders[name].position_output_port(), station.diagram.GetInputPort(f"{name}.position")
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
        #: What the arms' plans avoid besides the static cell and the other arm
        #: (MoveIt's planning scene: loose parts are not in it unless added).
        self.planning_scene = CellPlanningScene(self.runtime, self.tf)
        self._move_steps = MoveSteps()
        self._arms = {
            name: Arm(self.runtime, self.tf, name, c, self.planning_scene, self._move_steps)
            for name, c in commanders.items()
        }
        self._closed = False
        self._final_ledger: Optional[Ledger] = None

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
        if name not in self._arms and name in self.station.models:
            raise NotSupportedError(
                f"robot {name!r} is a model from a description file: arm(), gripper() and MoveIt need "
                f"one of the scenario's UR arms ({', '.join(self._arms) or 'none here'}); move its joints "
                "with its gazebo_ros plugins (/set_joint_trajectory)"
            )
        if name not in self._arms:
            raise UnknownNameError("robot", name, self._arms)
        return self._arms[name]

    def gripper(self, robot: str) -> Gripper:
        if robot in self.station.models:
            self.arm(robot)  # the error says what needs a UR arm
        self.station.suction_name(robot)  # the error lists the robots with grippers
        return Gripper(self.runtime, robot)

    def bin(self, name: str) -> Bin:
        """Bin ``name``: its pose, inner size and a free drop point for a part."""
        bins = {b.name: b for b in self.scenario.bins}
        if name not in bins:
            raise UnknownNameError("bin", name, bins)
        return Bin(self.runtime, bins[name])

    def camera(self, name: str) -> Camera:
        self.runtime.camera_image(name)  # the error lists the cameras
        return Camera(self.runtime, name)

    # ------------------------------------------------------------ time

    def on_move_step(self, hook: Callable[[], None]) -> None:
        """Calls ``hook()`` between the steps of every blocking move (every 10-50 ms of
        simulated time, after the contact check), e.g. to run other work while an
        arm moves (the ROS layer delivers topic callbacks there). The hook may make
        blocking calls itself; the move goes on from wherever they leave the cell."""
        self._move_steps.hooks.append(hook)

    def limit_move_steps(self, next_stop: Callable[[], float]) -> None:
        """Every blocking move's next step ends no later than ``next_stop()`` (simulated
        seconds; a time not after now is ignored), so that the work its step hooks do
        for that time runs on time (the ROS layer's other script threads wake there)."""
        self._move_steps.stops.append(next_stop)

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
        wait_until(self.runtime, condition, timeout, period=period, what=what)

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
        """Where every part is (after :meth:`close`: where each was when it closed)."""
        return self._final_ledger if self._final_ledger is not None else self.runtime.ledger()

    def faults(self) -> list[FaultReport]:
        """The scenario's faults that have struck so far: what, when, and their effect."""
        return list(self.runtime.faults.reports) if self.runtime.faults is not None else []

    def world_pose(self, pose: RigidTransform | PoseStamped) -> RigidTransform:
        """A pose in world: a RigidTransform is one already; a PoseStamped is transformed
        with tf at its time."""
        return world_pose(self.tf, pose)

    # ------------------------------------------------------------ the end

    def close(self) -> Optional[Path]:
        """Writes the replay (with ``record``) and returns its path; frees the cell
        (:meth:`FactoryRuntime.close <omtp_drake.sim.runtime.FactoryRuntime.close>`).
        Afterwards :attr:`time`, :meth:`ledger` and :meth:`faults` tell how it ended;
        running it raises SimulationError. Closing twice is harmless."""
        if self._closed:
            return None
        self._closed = True
        try:
            self._final_ledger = self.runtime.ledger()
            if self._record is not None and self.meshcat is not None:
                return save_recording(self.station.visualizer, self.meshcat, self._record)
            return None
        finally:
            self.runtime.close()

    def __enter__(self) -> Cell:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _cell_scenario(
    scenario: Scenario | str | None,
    launch: Optional[str],
    world: Optional[str | Path],
    robot: Optional[str | Path],
    workspace: Sequence[str | Path] | str | Path,
) -> Scenario:
    """The scenario a Cell builds: the cell of ``scenario``, ``launch`` or ``world`` (Gazebo's
    empty world when none is given with a ``robot``), with ``robot`` spawned in it."""
    if scenario is None and not (launch or world or robot):
        raise ConfigError("Cell needs a scenario (a name, path or Scenario), a launch=, a world= or a robot=")
    spawns = [RobotSpawn(os.fspath(robot))] if robot else []
    own = cell_of(scenario, launch=launch, world=world, robots=spawns, workspace=workspace)
    for line in own.warnings + own.ros_only:
        _log.warning("%s", line)
    return own.scenario
