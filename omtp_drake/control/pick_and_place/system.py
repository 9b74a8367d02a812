"""The pick-and-place controller of one robot as a Drake system: a thin
``LeafSystem`` around the state machine
(:class:`~omtp_drake.control.pick_and_place.machine.PickMachine`), and the
``add_pick_and_place`` factory that wires it and Drake's DiffIK to a station.

The controller perceives parts **only through logical cameras** (the part's pose is
the camera's ``X_WC`` times the reported ``X_CM``) and its own arm's joint
encoders; it never reads ground truth. It asks :mod:`omtp_drake.control.pick_policy`
for tool paths of the suction-cup face (``<gripper>_tip``) and feeds them, as desired
poses, to Drake's ``DifferentialInverseKinematicsIntegrator``, whose joint positions
drive the arm's position servo.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import (
    DifferentialInverseKinematicsIntegrator,
    DifferentialInverseKinematicsParameters,
)
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import (
    Context,
    DiagramBuilder,
    InputPort,
    LeafSystem,
    OutputPort,
    State,
    ValueProducer,
)
from pydrake.systems.primitives import ConstantValueSource

from omtp_drake.cell import arms
from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.pick_and_place.controller_state import ControlState, PickHistory
from omtp_drake.control.pick_and_place.machine import PickMachine
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
        - X_BE_desired
        - use_robot_state
        - suction_command
        - control
        - history

    Input ports:
      - ``camera_image``: the pick camera's LogicalCameraImage.
      - ``bin_camera_image``: the bin camera's image (time NaN without one), to
        verify a place and to find the bin.
      - ``search_camera_<k>`` (``search_cameras`` of them): the other cameras'
        images, to find a part that fell out of the pick camera's view.
      - ``gripper_state``: the robot's GripperState (``enabled``, ``attached``).
      - ``robot_state``: the arm's measured [q; v].

    Output ports:
      - ``X_BE_desired`` (RigidTransform): desired pose of the cup face E in the
        arm's base frame B, for DiffIK.
      - ``use_robot_state`` (bool): ask DiffIK to restart from the measured q.
      - ``suction_command`` (vector [0 or 1]).
      - ``control`` (:class:`ControlState`), ``history`` (:class:`PickHistory`).

    Each periodic update (at ``update_rate_hz``) reads the input ports into a
    :class:`~omtp_drake.control.pick_and_place.machine_io.MachineInput` (the cameras'
    only when the machine asks for an image), asks the
    machine for its decision and writes it into the state. State (abstract): the
    control state and the history. A scratch Context of the arm's model, for forward
    kinematics of the measured joints, is a cache entry (it depends on
    ``robot_state`` only). So is the path's pose table (:class:`PoseTable`): the
    desired pose at each of DiffIK's sample times (``diffik_rate_hz``), computed in
    one numpy call when the path changes, so that DiffIK's request every step is a
    lookup.

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
        self._X_BW = self._X_WB.inverse()
        home_context = control_plant.CreateDefaultContext()
        control_plant.SetPositions(home_context, np.asarray(arms.named_pose("Home", robot)))
        X_W_home = self._X_WB @ self._tip.CalcPoseInWorld(home_context)
        self._machine = PickMachine(config, robot, bin, part_size, X_W_home)
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
        self._diffik_period = 1.0 / config.diffik_rate_hz
        self._table = self.DeclareCacheEntry(
            description="desired tool poses at DiffIK's sample times",
            value_producer=ValueProducer(
                allocate=AbstractValue.Make(PoseTable()).Clone, calc=weak_method(self._calc_table)
            ),
            prerequisites_of_calc={self.abstract_state_ticket(self._control)},
        )
        self._history = self.DeclareAbstractState(AbstractValue.Make(PickHistory()))
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
        self._robot_state = self.DeclareVectorInputPort("robot_state", 2 * self._plant.num_positions())

    def _declare_output_ports(self) -> None:
        """The ports of the class doc's "Output ports" list."""
        control_ticket = {self.abstract_state_ticket(self._control)}
        self._pose_port = self.DeclareAbstractOutputPort(
            "X_BE_desired",
            lambda: AbstractValue.Make(RigidTransform()),
            weak_method(self._calc_pose),
            prerequisites_of_calc=control_ticket
            | {self.time_ticket(), self.input_port_ticket(self._robot_state.get_index())},
        )
        control = self._control  # (C++ holds these callbacks: they must not hold self)
        self._use_robot_state_port = self.DeclareAbstractOutputPort(
            "use_robot_state",
            lambda: AbstractValue.Make(False),
            lambda c, out: out.set_value(c.get_abstract_state(control).get_value().reset_ik),
            prerequisites_of_calc=control_ticket,
        )
        self._suction_port = self.DeclareVectorOutputPort(
            "suction_command",
            1,
            lambda c, out: out.SetAtIndex(0, float(c.get_abstract_state(control).get_value().suction)),
            prerequisites_of_calc=control_ticket,
        )
        self._control_port = self.DeclareStateOutputPort("control", self._control)
        self._history_port = self.DeclareStateOutputPort("history", self._history)

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

    def tool_pose_output_port(self) -> OutputPort:
        """``X_BE_desired``: the desired cup-face pose in the arm's base, for DiffIK."""
        return self._pose_port

    def use_robot_state_output_port(self) -> OutputPort:
        """``use_robot_state``: DiffIK restarts from the measured joints."""
        return self._use_robot_state_port

    def suction_command_output_port(self) -> OutputPort:
        """``suction_command``: [1] suction on, [0] off."""
        return self._suction_port

    def control_output_port(self) -> OutputPort:
        """``control``: the :class:`ControlState` (what the controller is doing)."""
        return self._control_port

    def history_output_port(self) -> OutputPort:
        """``history``: the :class:`PickHistory` (what it has done)."""
        return self._history_port

    # ------------------------------------------------------------ calculations

    def _control_state(self, context: Context) -> ControlState:
        return context.get_abstract_state(self._control).get_value()

    def _calc_scratch(self, context: Context, value: AbstractValue) -> None:
        self._plant.SetPositions(value.get_mutable_value(), self._robot_state.Eval(context)[: self._nq])

    def _fk(self, context: Context) -> RigidTransform:
        """``X_WE`` at the measured joints."""
        return self._X_WB @ self._tip.CalcPoseInWorld(self._scratch.Eval(context))

    def _calc_table(self, context: Context, value: AbstractValue) -> None:
        # Runs after every update (an update marks all of the state changed); the
        # table is refilled only when the path is a new one.
        table: PoseTable = value.get_mutable_value()
        path = context.get_abstract_state(self._control).get_value().path
        if table.path is not path:
            table.fill(path, context.get_time(), self._diffik_period, self._X_BW)

    def _calc_pose(self, context: Context, output: AbstractValue) -> None:
        # DiffIK asks at every one of its steps: a lookup in the table, as a rule.
        t = context.get_time()
        X_BE = self._table.Eval(context).pose(t)
        if X_BE is None:  # not a sample time of the table
            X_WE = self._control_state(context).pose_at(t)
            if X_WE is None:
                X_WE = self._fk(context)
            X_BE = self._X_BW @ X_WE
        output.set_value(X_BE)

    def _update(self, context: Context, state: State) -> None:
        """Reads the arm's and the gripper's ports, and a camera's only if the machine
        asks for its image (a camera computes an image when it is read); asks the
        machine; writes its decision."""
        s = self._control_state(context)
        t = context.get_time()
        X_BE = self._table.Eval(context).pose(t)  # the path at t, as DiffIK gets it
        inputs = MachineInput(
            t=t,
            X_WE=self._fk(context),
            gripper=self._gripper.Eval(context),
            q=tuple(self._robot_state.Eval(context)[: self._nq].tolist()),
            read_pick_image=lambda: self._image.Eval(context),
            read_bin_image=lambda: self._bin_image.Eval(context),
            read_search_images=lambda: tuple(port.Eval(context) for port in self._search_images),
            X_WE_desired=None if X_BE is None else self._X_WB @ X_BE,
        )
        decision = self._machine.step(inputs, s)
        if decision.control is not s:
            state.get_mutable_abstract_state(self._control).set_value(decision.control)
        history: PickHistory = context.get_abstract_state(self._history).get_value()
        updated = history.with_step(decision.record, decision.tracking_error)
        if updated is not history:
            state.get_mutable_abstract_state(self._history).set_value(updated)


class PoseTable:
    """A path's desired tool poses ``X_BE`` at the sample times ``k h`` from the
    first at or after ``t`` (when the path was first asked for) to the path's end,
    from one :meth:`~omtp_drake.control.tool_paths.Path.poses` call. Mutable: the
    value of the controller's cache entry, refilled when the path changes.

    The transforms are built in one loop when the table is filled: a lookup at
    DiffIK's rate then only indexes a list, instead of building a transform between
    plant steps (figures: bench/README.md, "Measured")."""

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


def add_pick_and_place(
    builder: DiagramBuilder, station, config: TaskConfig
) -> tuple[PickAndPlaceController, DifferentialInverseKinematicsIntegrator]:
    """Adds the controller and DiffIK of ``config.robot`` around ``station`` (a Station
    already added to ``builder``) and connects them to its ports."""
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
    diffik = builder.AddSystem(_diffik(plant, robot, config.diffik_rate_hz))

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
    builder.Connect(controller.tool_pose_output_port(), diffik.GetInputPort("X_AE_desired"))
    builder.Connect(controller.use_robot_state_output_port(), diffik.GetInputPort("use_robot_state"))
    builder.Connect(d.GetOutputPort(f"{robot.name}.state_estimated"), diffik.GetInputPort("robot_state"))
    builder.Connect(diffik.GetOutputPort("joint_positions"), d.GetInputPort(f"{robot.name}.position"))
    builder.Connect(controller.suction_command_output_port(), d.GetInputPort(f"{suction}.command"))
    return controller, diffik


def _diffik(
    plant: MultibodyPlant, robot: RobotConfig, rate_hz: float
) -> DifferentialInverseKinematicsIntegrator:
    """Drake's DiffIK on the arm's model: the tip frame, the arm's joint velocity
    and position limits, joints centred on Home."""
    params = DifferentialInverseKinematicsParameters(plant.num_positions(), plant.num_velocities())
    params.set_time_step(1.0 / rate_hz)
    vmax = np.array(arms.VELOCITY_LIMITS[robot.model])
    params.set_joint_velocity_limits((-vmax, vmax))
    params.set_joint_position_limits((np.full(6, -robot.joint_limit), np.full(6, robot.joint_limit)))
    params.set_nominal_joint_position(arms.named_pose("Home", robot))
    params.set_joint_centering_gain(0.05 * np.eye(6))
    diffik = DifferentialInverseKinematicsIntegrator(
        plant, plant.world_frame(), plant.GetFrameByName(f"{robot.gripper}_tip"), 1.0 / rate_hz, params
    )
    diffik.set_name(f"{robot.name}.diffik")
    return diffik


def history_of(controller: PickAndPlaceController, root_context: Context) -> PickHistory:
    """The controller's pick history in a Context of a diagram holding it."""
    return controller.history_output_port().Eval(controller.GetMyContextFromRoot(root_context))


def control_of(controller: PickAndPlaceController, root_context: Context) -> ControlState:
    """The controller's control state in a Context of a diagram holding it."""
    return controller.control_output_port().Eval(controller.GetMyContextFromRoot(root_context))
