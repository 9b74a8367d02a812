"""The pick-and-place controller of one robot as a Drake system: a thin
``LeafSystem`` around the state machine
(:class:`~omtp_drake.control.pick_and_place.machine.PickMachine`), and the
``add_pick_and_place`` factory that wires it and its jerk stream to a station.

The controller perceives parts **only through logical cameras** (the part's pose is
the camera's ``X_WC`` times the reported ``X_CM``) and its own arm's joint
encoders; it never reads ground truth. It asks :mod:`omtp_drake.control.pick_policy`
for tool paths of the suction-cup face (``<gripper>_tip``); when it decides one, Drake's
differential IK is integrated along it at once into a joint plan
(:mod:`omtp_drake.control.joint_plan`), which a C++ ``LinearSystem`` plays to the arm's
position servo between the controller's updates.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import (
    Context,
    DiagramBuilder,
    EventStatus,
    InputPort,
    LeafSystem,
    OutputPort,
    State,
    ValueProducer,
)
from pydrake.systems.primitives import ConstantValueSource, Demultiplexer

from omtp_drake.cell import arms
from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.joint_plan import JerkStream, JointPlan, PlanAhead
from omtp_drake.control.pick_and_place.controller_state import ControlState, PickHistory, PickRecord
from omtp_drake.control.pick_and_place.machine import PickMachine, travel_check
from omtp_drake.control.pick_and_place.machine_io import NO_IMAGE, MachineInput
from omtp_drake.control.tool_paths import Path
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import BinConfig, RobotConfig, TaskConfig


class PickAndPlaceController(LeafSystem):
    """The pick-and-place state machine of one robot, as a system.

    .. pydrake_system::

        name: PickAndPlaceController
        input_ports:
        - camera_image
        - bin_camera_image
        - search_camera_<k>
        - gripper_state
        - robot_state
        output_ports:
        - jerk
        - suction_command
        - control
        - history
        - joint_plan

    Input ports:
      - ``camera_image``: the pick camera's LogicalCameraImage.
      - ``bin_camera_image``: the bin camera's image (time NaN without one), to
        verify a place and to find the bin.
      - ``search_camera_<k>`` (``search_cameras`` of them): the other cameras'
        images, to find a part that fell out of the pick camera's view.
      - ``gripper_state``: the robot's GripperState (``enabled``, ``attached``).
      - ``robot_state``: the arm's measured [q; v].

    Output ports:
      - ``jerk`` (vector, n): the jerk the stream plays until the next update.
      - ``suction_command`` (vector [0 or 1]).
      - ``control`` (:class:`ControlState`), ``history`` (:class:`PickHistory`),
        ``joint_plan`` (:class:`~omtp_drake.control.joint_plan.JointPlan`).

    Each periodic update (at ``update_rate_hz``) reads the input ports into a
    :class:`~omtp_drake.control.pick_and_place.machine_io.MachineInput` (the cameras'
    only when the machine asks for an image), asks the machine for its decision and
    writes it into the state. When the decision is a new tool path, DiffIK is
    integrated along it at once into a joint plan
    (:class:`~omtp_drake.control.joint_plan.PlanAhead`; from the measured joints when
    the machine restarts the arm after a tracking failure). ``jerk`` is the plan's jerk of
    its next period: the stream's hold samples it at the update times (after the update)
    and the stream (C++) integrates it at ``diffik_rate_hz``. State (all in the Context,
    changed only by the update): the control state, the history and the plan (abstract).
    An update that decides nothing (most: the arm travels, the machine waits) says
    ``DidNothing``: the state and what depends on it stay as they are, unless another
    system's update at that time changed (Drake applies a diagram's together). Cache: a
    scratch Context of the arm's model (forward kinematics of ``robot_state``) and the
    path's :class:`PoseTable` (the desired tool pose at each update time).

    Frames: W world, B the arm's base_link, E ``<gripper>_tip`` (the cup face,
    +z out of the tool), C a camera, P a part's origin (its centre).
    """

    def __init__(
        self,
        config: TaskConfig,
        robot: RobotConfig,
        bin: BinConfig,
        control_plant: MultibodyPlant,
        part_size: Callable[[str], float],
        search_cameras: int = 0,
    ):
        super().__init__()
        config.validate()
        self._plant = control_plant
        self._nq = control_plant.num_positions()
        self._tip = control_plant.GetFrameByName(f"{robot.gripper}_tip")
        self._X_WB = arms.base_pose(robot)
        home_context = control_plant.CreateDefaultContext()
        control_plant.SetPositions(home_context, np.asarray(arms.named_pose("Home", robot)))
        X_W_home = self._X_WB @ self._tip.CalcPoseInWorld(home_context)
        self._machine = PickMachine(config, robot, bin, part_size, X_W_home)
        self._tolerance = config.tracking_tolerance
        self._motion = PlanAhead(
            control_plant, robot, self._X_WB, 1.0 / config.update_rate_hz, stream_step(config)
        )
        self.set_name(f"{robot.name}.pick_and_place")
        self._declare_input_ports(search_cameras)
        self._scratch = self.DeclareCacheEntry(
            description="arm model at the measured joints",
            value_producer=ValueProducer(
                allocate=AbstractValue.Make(control_plant.CreateDefaultContext()).Clone,
                calc=weak_method(self._calc_scratch),
            ),
            prerequisites_of_calc={self.input_port_ticket(self._robot_state.get_index())},
        )
        self._control = self.DeclareAbstractState(AbstractValue.Make(ControlState()))
        self._history = self.DeclareAbstractState(AbstractValue.Make(PickHistory()))
        q0 = arms.named_pose(robot.initial_pose, robot)
        self._plan = self.DeclareAbstractState(
            AbstractValue.Make(JointPlan.hold(0.0, self._motion.period, q0))
        )
        self._table = self.DeclareCacheEntry(
            description="desired tool poses at the update times",
            value_producer=ValueProducer(
                allocate=AbstractValue.Make(PoseTable()).Clone, calc=weak_method(self._calc_table)
            ),
            prerequisites_of_calc={self.abstract_state_ticket(self._control)},
        )
        self._declare_output_ports()
        self.DeclarePeriodicUnrestrictedUpdateEvent(1.0 / config.update_rate_hz, 0.0, self._update)

    # ------------------------------------------------------------------ ports

    def _declare_input_ports(self, search_cameras: int) -> None:
        """The ports of the class doc's "Input ports" list."""
        no_image = AbstractValue.Make(NO_IMAGE)
        self._image = self.DeclareAbstractInputPort("camera_image", no_image)
        self._bin_image = self.DeclareAbstractInputPort("bin_camera_image", no_image)
        self._search_images = [
            self.DeclareAbstractInputPort(f"search_camera_{k}", no_image) for k in range(search_cameras)
        ]
        self._gripper = self.DeclareAbstractInputPort(
            "gripper_state", AbstractValue.Make(GripperState(False, False, "", None, math.nan))
        )
        self._robot_state = self.DeclareVectorInputPort("robot_state", 2 * self._nq)

    def _declare_output_ports(self) -> None:
        """The ports of the class doc's "Output ports" list."""
        control = self._control  # (C++ holds these callbacks: they must not hold self)
        motion, plan = self._motion, self._plan
        self._jerk_port = self.DeclareVectorOutputPort(
            "jerk",
            self._nq,
            lambda c, y: y.SetFromVector(motion.jerk(c.get_abstract_state(plan).get_value(), c.get_time())),
            {self.time_ticket(), self.abstract_state_ticket(plan)},
        )
        self._suction_port = self.DeclareVectorOutputPort(
            "suction_command",
            1,
            lambda c, out: out.SetAtIndex(0, float(c.get_abstract_state(control).get_value().suction)),
            prerequisites_of_calc={self.abstract_state_ticket(control)},
        )
        self._control_port = self.DeclareStateOutputPort("control", self._control)
        self._history_port = self.DeclareStateOutputPort("history", self._history)
        self._plan_port = self.DeclareStateOutputPort("joint_plan", self._plan)

    def camera_image_input_port(self) -> InputPort:
        """``camera_image``: the pick camera's LogicalCameraImage."""
        return self._image

    def bin_camera_image_input_port(self) -> InputPort:
        """``bin_camera_image``: the bin camera's LogicalCameraImage."""
        return self._bin_image

    def search_camera_input_port(self, k: int) -> InputPort:
        """``search_camera_<k>``: the image of the k-th other camera."""
        if not 0 <= k < len(self._search_images):
            raise ConfigError(f"search camera index must be in [0, {len(self._search_images)}), got {k}")
        return self._search_images[k]

    def gripper_state_input_port(self) -> InputPort:
        """``gripper_state``: the gripper's GripperState."""
        return self._gripper

    def robot_state_input_port(self) -> InputPort:
        """``robot_state``: the arm's measured [q; v]."""
        return self._robot_state

    def jerk_output_port(self) -> OutputPort:
        """``jerk``: what the jerk stream integrates until the next update."""
        return self._jerk_port

    def suction_command_output_port(self) -> OutputPort:
        """``suction_command``: [1] suction on, [0] off."""
        return self._suction_port

    def control_output_port(self) -> OutputPort:
        """``control``: the :class:`ControlState` (what the controller is doing)."""
        return self._control_port

    def history_output_port(self) -> OutputPort:
        """``history``: the :class:`PickHistory` (what it has done)."""
        return self._history_port

    def joint_plan_output_port(self) -> OutputPort:
        """``joint_plan``: the :class:`~omtp_drake.control.joint_plan.JointPlan` played."""
        return self._plan_port

    # ------------------------------------------------------------ calculations

    def _control_state(self, context: Context) -> ControlState:
        return context.get_abstract_state(self._control).get_value()

    def _calc_scratch(self, context: Context, value: AbstractValue) -> None:
        self._plant.SetPositions(value.get_mutable_value(), self._robot_state.Eval(context)[: self._nq])

    def _fk(self, context: Context) -> RigidTransform:
        """``X_WE`` at the measured joints."""
        return self._X_WB @ self._tip.CalcPoseInWorld(self._scratch.Eval(context))

    def _calc_table(self, context: Context, value: AbstractValue) -> None:
        # Runs after each update that changed the state: refilled for a new path only.
        table: PoseTable = value.get_mutable_value()
        path = context.get_abstract_state(self._control).get_value().path
        if table.path is not path:
            table.fill(path, context.get_time(), self._motion.period, RigidTransform())

    def _update(self, context: Context, state: State) -> EventStatus:
        """Reads the arm's and the gripper's ports, and a camera's only if the machine
        asks for its image (a camera computes an image when it is read); asks the
        machine; writes its decision, a new plan for a new path, the history."""
        s = self._control_state(context)
        t = context.get_time()
        error = travel_check(  # the checks while the arm travels (reads only what they need)
            s,
            t,
            self._tolerance,
            lambda: self._gripper.Eval(context).attached,
            lambda: self._table.Eval(context).pose(t),
            lambda: self._fk(context),
        )
        if error is not None:  # they pass: nothing to decide
            return self._record(context, state, None, error)
        q = self._robot_state.Eval(context)[: self._nq]
        inputs = MachineInput(
            t=t,
            X_WE=self._fk(context),
            gripper=self._gripper.Eval(context),
            q=tuple(q.tolist()),
            read_pick_image=lambda: self._image.Eval(context),
            read_bin_image=lambda: self._bin_image.Eval(context),
            read_search_images=lambda: tuple(port.Eval(context) for port in self._search_images),
            X_WE_desired=self._table.Eval(context).pose(t),
        )
        decision = self._machine.step(inputs, s)
        recorded = self._record(context, state, decision.record, decision.tracking_error)
        if decision.control is s:
            return recorded
        state.get_mutable_abstract_state(self._control).set_value(decision.control)
        restart = decision.control.reset_ik and not s.reset_ik
        if decision.control.path is not s.path or restart:
            played: JointPlan = context.get_abstract_state(self._plan).get_value()
            plan = self._motion.plan(decision.control.path, t, played, q if restart else None)
            state.get_mutable_abstract_state(self._plan).set_value(plan)
        return EventStatus.Succeeded()

    def _record(self, context: Context, state: State, record: Optional[PickRecord], e: float) -> EventStatus:
        """The history with ``record`` and tracking error ``e``: DidNothing if unchanged."""
        history: PickHistory = context.get_abstract_state(self._history).get_value()
        updated = history.with_step(record, e)
        if updated is history:
            return EventStatus.DidNothing()
        state.get_mutable_abstract_state(self._history).set_value(updated)
        return EventStatus.Succeeded()


class PoseTable:
    """A path's desired tool poses ``X_BE`` at the sample times ``k h`` from the
    first at or after ``t`` (when the path was first asked for) to the path's end,
    from one :meth:`~omtp_drake.control.tool_paths.Path.poses` call. Mutable: the
    value of the controller's cache entry, refilled when the path changes.

    The controller's updates look the path up here (``h`` its period) for the
    machine's tracking check, instead of evaluating it at every update."""

    def __init__(self) -> None:
        self.path: Optional[Path] = None
        self._k0, self._h = 0, 1.0
        self._X_BE: list[RigidTransform] = []

    def fill(self, path: Path, t: float, h: float, X_BW: RigidTransform) -> None:
        """The table of ``path`` (sample period ``h``) from ``t`` on."""
        self.path, self._h = path, h
        self._k0 = math.ceil(t / h - 1e-6)
        if not path.segments:
            self._X_BE = []
            return
        k1 = max(self._k0, math.ceil(path.end_time / h)) + 1
        p_WE, R_WE = path.poses(np.arange(self._k0, k1 + 1) * h)
        R_BW = X_BW.rotation().matrix()
        # The last is the end pose, asked for at every sample once the path is done
        # (an arm that waits holds it).
        R_BE, p_BE = R_BW @ R_WE, p_WE @ R_BW.T + X_BW.translation()
        self._X_BE = [RigidTransform(RotationMatrix(R), p) for R, p in zip(R_BE, p_BE)]

    def pose(self, t: float) -> Optional[RigidTransform]:
        """``X_BE`` at ``t`` if ``t`` is one of the table's sample times (after its
        last, the path's end pose), else None."""
        h, X_BE = self._h, self._X_BE
        k = round(t / h)
        i = k - self._k0
        if i < 0 or not X_BE or abs(t - k * h) > 1e-9:
            return None
        return X_BE[i] if i < len(X_BE) else X_BE[-1]

    def __deepcopy__(self, memo: dict) -> PoseTable:
        return PoseTable()  # a cache: a cloned Context refills its own


def stream_step(config: TaskConfig) -> float:
    """The jerk stream's step: DiffIK's (``1 / diffik_rate_hz``), a whole number of which
    make the controller's period (ConfigError if not)."""
    h, period = 1.0 / config.diffik_rate_hz, 1.0 / config.update_rate_hz
    steps = round(period / h)
    if steps < 1 or abs(steps * h - period) > 1e-9 * period:
        raise ConfigError(
            f"task.diffik_rate_hz ({config.diffik_rate_hz:g}) must be a whole multiple of "
            f"task.update_rate_hz ({config.update_rate_hz:g}): the arm's command changes its "
            "jerk at the controller's updates"
        )
    return h


def add_pick_and_place(
    builder: DiagramBuilder, station, config: TaskConfig
) -> tuple[PickAndPlaceController, JerkStream]:
    """Adds the controller of ``config.robot`` and its jerk stream around ``station`` (a
    Station already added to ``builder``) and connects them to its ports."""
    config.validate()
    scenario = station.scenario
    handles = station.arm(config.robot)
    robot = handles.config
    if not robot.gripper:
        raise ConfigError(f"{robot.name} has no gripper to pick with")
    plant = handles.control_plant
    search = sorted(set(station.cameras) - {config.camera, config.bin_camera})
    controller = builder.AddSystem(
        PickAndPlaceController(
            config, robot, scenario.bin(config.bin), plant, scenario.part_size, search_cameras=len(search)
        )
    )
    n = plant.num_positions()
    q0 = arms.named_pose(robot.initial_pose, robot)
    stream = builder.AddSystem(
        JerkStream(q0, stream_step(config), 1.0 / config.update_rate_hz, f"{robot.name}.joint_stream")
    )
    command = builder.AddNamedSystem(f"{robot.name}.joint_command", Demultiplexer([n, 2 * n]))

    d = station.diagram
    if config.camera not in station.cameras:
        raise ConfigError(f"task.camera {config.camera!r} is not a camera of the station")
    builder.Connect(d.GetOutputPort(f"{config.camera}.image"), controller.camera_image_input_port())
    if config.bin_camera:
        builder.Connect(
            d.GetOutputPort(f"{config.bin_camera}.image"), controller.bin_camera_image_input_port()
        )
    else:
        empty = builder.AddSystem(ConstantValueSource(AbstractValue.Make(NO_IMAGE)))
        builder.Connect(empty.get_output_port(), controller.bin_camera_image_input_port())
    for k, camera in enumerate(search):
        builder.Connect(d.GetOutputPort(f"{camera}.image"), controller.search_camera_input_port(k))
    suction = station.suction_name(config.robot)
    builder.Connect(d.GetOutputPort(f"{suction}.state"), controller.gripper_state_input_port())
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"), controller.robot_state_input_port())
    builder.Connect(controller.jerk_output_port(), stream.get_input_port())
    builder.Connect(stream.get_output_port(), command.get_input_port())
    builder.Connect(command.get_output_port(0), d.GetInputPort(f"{robot.name}.position"))
    builder.Connect(controller.suction_command_output_port(), d.GetInputPort(f"{suction}.command"))
    return controller, stream


def history_of(controller: PickAndPlaceController, root_context: Context) -> PickHistory:
    """The controller's pick history in a Context of a diagram holding it."""
    return controller.history_output_port().Eval(controller.GetMyContextFromRoot(root_context))


def control_of(controller: PickAndPlaceController, root_context: Context) -> ControlState:
    """The controller's control state in a Context of a diagram holding it."""
    return controller.control_output_port().Eval(controller.GetMyContextFromRoot(root_context))
