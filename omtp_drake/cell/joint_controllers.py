"""The joints of any robot driven as ros_control / ros2_control drive them in Gazebo.

A model whose description has a ``gazebo_ros_control`` or ``gazebo_ros2_control``
plugin (:class:`~omtp_drake.scenario.ros_control.RosControlConfig`) gets one actuator
per hardware joint (the URDF's transmission's, or one added for a ``<ros2_control>``
joint) with Drake's PD control in the plant, by the joint's command interface:

=========  ============================  =============================================
interface  PD gains (p, d)               what the command sets
=========  ============================  =============================================
position   stiff: 1e5, 1e3 (SAP, an      the desired position and velocity (Gazebo sets
           implicit PD: stable)          the joint's position; here it follows within
                                         the effort limit, ~10 ms behind)
velocity   0, 1e3                        the desired velocity
effort     the controller's ``p``, ``d``  desired position/velocity of a PID controller
           (0, 0 without one)            (``effort_controllers/*``); a raw effort is a
                                         feed-forward torque
=========  ============================  =============================================

A PID's integral term (``i``, clamped to ``+-i_clamp``) is a feed-forward effort from a
discrete integral of the position error, one update per plant step; a velocity trajectory
controller adds ``p`` and ``d`` times its errors to the commanded velocity.
:class:`JointControllers` is the system that holds every controller's command in its
Context (abstract state, changed between advances by :meth:`JointControllers.command`) and
outputs, per model, the desired state (``<model>.desired_state``) and feed-forward effort
(``<model>.feedforward``) the plant's PD actuators take.

Port block::

                  +------------------+
    plant_state ->| JointControllers |-> <model>.desired_state (2 n_actuators)
                  |                  |-> <model>.feedforward   (n_actuators)
                  +------------------+
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JointActuator, ModelInstanceIndex, PdControllerGains
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem

from omtp_drake.cell.joint_splines import JointSpline
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import ModelConfig
from omtp_drake.scenario.ros_control import ControllerConfig, HardwareJoint, PidGains, RosControlConfig

#: The stiff PD of a position-commanded joint (N m / rad, N m s / rad; implicit in SAP).
POSITION_GAINS = (1e5, 1e3)
#: The damping of a velocity-commanded joint (N m s / rad).
VELOCITY_DAMPING = 1e3


@dataclass(frozen=True)
class DrivenJoint:
    """A hardware joint: its model, name, command interface, its controller (None: no
    controller claims it) and where it is in the plant."""

    model: str
    name: str
    interface: str
    controller: Optional[str]
    q_index: int
    v_index: int
    #: The controller's PID gains for the joint (zero: none).
    gains: PidGains = field(default_factory=PidGains)


@dataclass(frozen=True)
class Command:
    """What a controller (or an unclaimed joint) asks of its joints now: a ``spline`` to
    follow (positions), or constant ``velocities`` or ``efforts``."""

    joints: tuple[str, ...]
    spline: Optional[JointSpline] = None
    velocities: Optional[tuple[float, ...]] = None
    efforts: Optional[tuple[float, ...]] = None
    #: Tells one command from the next (an action goal watches whether its command still plays).
    tag: int = 0


#: The target of an actuated joint no command covers (no gains either): none.
_FREE = (np.nan, 0.0, 0.0)


def _key(model: str, name: str) -> str:
    return f"{model}/{name}"


@dataclass
class DrivePlan:
    """What :func:`declare_joint_drives` set up before the plant was finalized."""

    #: model -> its ros_control set-up.
    configs: dict[str, RosControlConfig] = field(default_factory=dict)
    #: model -> (joint name, actuator) in the instance's actuator order.
    actuators: dict[str, list[tuple[str, JointActuator]]] = field(default_factory=dict)


def declare_joint_drives(
    plant: MultibodyPlant, models: Sequence[ModelConfig], instances: Mapping[str, ModelInstanceIndex]
) -> DrivePlan:
    """Actuators with PD gains on every hardware joint of ``models`` (before Finalize)."""
    plan = DrivePlan()
    existing = {plant.get_joint_actuator(i).joint().index(): plant.get_joint_actuator(i)
                for i in plant.GetJointActuatorIndices()}  # fmt: skip
    for model in models:
        config = model.gazebo.ros_control
        if config is None:
            continue
        claims = {j: c for c in config.controllers if c.kind != "joint_states" for j in c.joints}
        plan.configs[model.name] = config
        plan.actuators[model.name] = []
        for hardware in config.joints:
            if not plant.HasJointNamed(hardware.name, instances[model.name]):
                raise ConfigError(
                    f"{model.file}: ros_control joint {hardware.name!r} is no joint of the model"
                )
            joint = plant.GetJointByName(hardware.name, instances[model.name])
            actuator = existing.pop(joint.index(), None)
            if actuator is None and not hardware.command_interfaces:
                continue  # a joint with state interfaces only: reported, not driven
            if actuator is None:
                actuator = plant.AddJointActuator(f"{hardware.name}_actuator", joint)
            controller = claims.get(hardware.name)
            p, d = _gains(_interface(hardware, controller), hardware.name, controller)
            actuator.set_controller_gains(PdControllerGains(p=p, d=d))
            plan.actuators[model.name].append((hardware.name, actuator))
        # Any other actuator of the model (a transmission the hardware does not list): free.
        for actuator in [a for a in existing.values() if a.model_instance() == instances[model.name]]:
            actuator.set_controller_gains(PdControllerGains(p=0.0, d=0.0))
            plan.actuators[model.name].append((actuator.joint().name(), actuator))
    return plan


def _interface(hardware: HardwareJoint, controller: Optional[ControllerConfig]) -> str:
    """How the joint is commanded: by its controller's interface, else its first command
    interface ("none": it has none)."""
    if controller is not None:
        return controller.interface
    return hardware.command_interfaces[0] if hardware.command_interfaces else "none"


def _gains(interface: str, joint: str, controller: Optional[ControllerConfig]) -> tuple[float, float]:
    if interface == "position":
        return POSITION_GAINS
    if interface == "velocity":
        return 0.0, VELOCITY_DAMPING
    if controller is not None and joint in controller.gains:
        return controller.gains[joint].p, controller.gains[joint].d
    return 0.0, 0.0


class JointControllers(LeafSystem):
    """Every started controller's command and the desired states it makes (module doc)."""

    def __init__(self, plant: MultibodyPlant, plan: DrivePlan, instances: Mapping[str, ModelInstanceIndex]):
        super().__init__()
        self.set_name("joint_controllers")
        #: Tags for the commands (:attr:`Command.tag`), one per command given.
        self.tags = itertools.count(1)
        self._plant = plant
        self.configs = plan.configs
        self.joints: dict[str, DrivenJoint] = {}
        self._order: dict[str, list[str]] = {}
        initial: dict[str, Command] = {}
        for model in plan.configs:
            by_actuator = sorted(plan.actuators[model], key=lambda pair: int(pair[1].index()))
            self._order[model] = [_key(model, name) for name, _ in by_actuator]
            initial |= self._model_commands(model, plan.configs[model], instances[model])
        self._commands_index = self.DeclareAbstractState(AbstractValue.Make(initial))
        self._state = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        #: The joints whose PID has an integral term (effort interface, ``i`` and ``i_clamp`` > 0).
        self._integrated = [
            k
            for k, j in self.joints.items()
            if j.interface == "effort" and j.gains.i > 0 and j.gains.i_clamp > 0
        ]
        self._integral_index = self.DeclareDiscreteState(max(1, len(self._integrated)))
        if self._integrated:
            self.DeclarePeriodicDiscreteUpdateEvent(plant.time_step(), 0.0, self._integrate)
        commands = self.abstract_state_ticket(self._commands_index)
        for model, keys in self._order.items():
            self.DeclareVectorOutputPort(
                f"{model}.desired_state",
                2 * len(keys),
                lambda c, out, m=model: out.SetFromVector(self._desired(c, m)),
                {commands, self.time_ticket(), self.all_input_ports_ticket()},
            )
            self.DeclareVectorOutputPort(
                f"{model}.feedforward",
                len(keys),
                lambda c, out, m=model: out.SetFromVector(self._feedforward(c, m)),
                {commands, self.xd_ticket(), self.time_ticket()},
            )

    def _model_commands(
        self, model: str, config: RosControlConfig, instance: ModelInstanceIndex
    ) -> dict[str, Command]:
        """The model's joints (recorded), each at its ``initial_value`` by default, and the
        commands at the start: each controller and each unclaimed joint holds its joints
        where they start (a velocity or effort command: zero)."""
        plant = self._plant
        for hardware in config.joints:
            if hardware.initial_position is not None:
                plant.GetJointByName(hardware.name, instance).set_default_positions(
                    [hardware.initial_position]
                )
        defaults = plant.GetPositions(plant.CreateDefaultContext())
        claims = {j: c for c in config.controllers if c.kind != "joint_states" for j in c.joints}
        initial: dict[str, Command] = {}
        listed = {h.name for h in config.joints}
        extra = [HardwareJoint(name=k.split("/", 1)[1], command_interfaces=[]) for k in self._order[model]]
        for hardware in [*config.joints, *(h for h in extra if h.name not in listed)]:
            joint = plant.GetJointByName(hardware.name, instance)
            controller = claims.get(hardware.name)
            interface = _interface(hardware, controller)
            key = _key(model, hardware.name)
            gains = controller.gains.get(hardware.name, PidGains()) if controller else PidGains()
            self.joints[key] = DrivenJoint(
                model, hardware.name, interface, controller.name if controller else None,
                joint.position_start(), joint.velocity_start(), gains,
            )  # fmt: skip
            if controller is None and interface != "none":
                initial[key] = self._rest(model, (hardware.name,), defaults, interface)
        for controller in config.controllers:
            if controller.kind != "joint_states":
                command = controller.command if controller.kind == "forward" else "position"
                initial[_key(model, controller.name)] = self._rest(
                    model, tuple(controller.joints), defaults, command
                )
        return initial

    def _rest(self, model: str, joints: tuple[str, ...], q: np.ndarray, command: str) -> Command:
        if command == "velocity":
            return Command(joints, velocities=(0.0,) * len(joints))
        if command == "effort":
            return Command(joints, efforts=(0.0,) * len(joints))
        positions = [
            q[self._plant.GetJointByName(j, self._model_instance(model)).position_start()] for j in joints
        ]
        return Command(joints, spline=JointSpline.hold(positions))

    def _model_instance(self, model: str) -> ModelInstanceIndex:
        return self._plant.GetModelInstanceByName(model)

    # ------------------------------------------------------------------ commands

    def commands(self, context: Context) -> dict[str, Command]:
        """``<model>/<controller or unclaimed joint>`` -> its command, in ``context``
        (this system's)."""
        return context.get_abstract_state(self._commands_index).get_value()

    def command(self, root_context: Context, model: str, controller: str, command: Command) -> None:
        """Gives ``controller`` of ``model`` a new command (between advances)."""
        context = self.GetMyMutableContextFromRoot(root_context)
        commands = dict(self.commands(context))
        commands[_key(model, controller)] = command
        context.get_mutable_abstract_state(self._commands_index).set_value(commands)

    def command_of(self, root_context: Context, model: str, controller: str) -> Command:
        """The command ``controller`` of ``model`` plays now."""
        return self.commands(self.GetMyContextFromRoot(root_context))[_key(model, controller)]

    def desired(self, root_context: Context, model: str, controller: str) -> tuple[np.ndarray, np.ndarray]:
        """(positions, velocities) ``controller``'s command asks of its joints now."""
        context = self.GetMyContextFromRoot(root_context)
        command = self.commands(context)[_key(model, controller)]
        if command.spline is None:
            return self.measured(root_context, model, command.joints)
        return command.spline.sample(context.get_time())

    def actuated_joints(self, model: str) -> list[str]:
        """``model``'s hardware joints in the order of its actuators (the plant's actuation ports)."""
        return [key.split("/", 1)[1] for key in self._order[model]]

    def measured(
        self, root_context: Context, model: str, joints: Sequence[str]
    ) -> tuple[np.ndarray, np.ndarray]:
        """(positions, velocities) of ``joints`` of ``model`` now."""
        x = self._plant.GetPositionsAndVelocities(self._plant.GetMyContextFromRoot(root_context))
        nq = self._plant.num_positions()
        driven = [self.joints[_key(model, j)] for j in joints]
        return np.array([x[j.q_index] for j in driven]), np.array([x[nq + j.v_index] for j in driven])

    # ------------------------------------------------------------------ outputs

    def _targets(self, context: Context, model: str) -> dict[str, tuple[float, float, float]]:
        """Joint key -> (q_d, v_d, feed-forward effort) of ``model``'s joints."""
        t = context.get_time()
        out: dict[str, tuple[float, float, float]] = {}
        for command in self.commands(context).values():
            keys = [_key(model, j) for j in command.joints]
            if not keys or keys[0] not in self.joints or self.joints[keys[0]].model != model:
                continue
            if command.spline is not None:
                q, v = command.spline.sample(t)
                out.update({k: (float(q[i]), float(v[i]), 0.0) for i, k in enumerate(keys)})
            elif command.velocities is not None:
                out.update({k: (np.nan, command.velocities[i], 0.0) for i, k in enumerate(keys)})
            elif command.efforts is not None:
                out.update({k: (np.nan, 0.0, command.efforts[i]) for i, k in enumerate(keys)})
        return out

    def _desired(self, context: Context, model: str) -> np.ndarray:
        """``[q_d; v_d]`` of ``model``'s actuators. A velocity-commanded joint following a
        trajectory gets the trajectory's velocity plus ``p`` times its position error and
        ``d`` times its velocity error (ros_controllers' velocity interface adapter)."""
        x = self._state.Eval(context)
        nq = self._plant.num_positions()
        targets = self._targets(context, model)
        q_d, v_d = [], []
        for key in self._order[model]:
            joint = self.joints[key]
            q, v, _ = targets.get(key, _FREE)
            q_now, v_now = x[joint.q_index], x[nq + joint.v_index]
            if np.isnan(q):
                q_d.append(q_now)
                v_d.append(v if joint.interface == "velocity" else v_now)
                continue
            if joint.interface == "velocity":
                v += joint.gains.p * (q - q_now) + joint.gains.d * (v - v_now)
            q_d.append(q)
            v_d.append(v)
        return np.concatenate([q_d, v_d])

    def _feedforward(self, context: Context, model: str) -> np.ndarray:
        """Raw efforts, plus each integrated joint's ``i`` term, ``i * integral`` clamped to
        ``+-i_clamp`` (control_toolbox's PID)."""
        targets = self._targets(context, model)
        out = np.array([targets.get(key, _FREE)[2] for key in self._order[model]])
        integral = context.get_discrete_state(self._integral_index).value()
        for k, key in enumerate(self._integrated):
            if key in self._order[model]:
                gains = self.joints[key].gains
                out[self._order[model].index(key)] += np.clip(
                    gains.i * integral[k], -gains.i_clamp, gains.i_clamp
                )
        return out

    def _integrate(self, context: Context, discrete_state) -> None:
        """Integrates the integrated joints' position errors over one plant step."""
        x = self._state.Eval(context)
        integral = np.array(context.get_discrete_state(self._integral_index).value())
        h = self._plant.time_step()
        targets: dict[str, tuple[float, float, float]] = {}
        for model in self._order:
            targets |= self._targets(context, model)
        for k, key in enumerate(self._integrated):
            q = targets[key][0]
            if not np.isnan(q):
                integral[k] += (q - x[self.joints[key].q_index]) * h
        discrete_state.get_mutable_vector(self._integral_index).SetFromVector(integral)


def add_joint_controllers(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    plan: DrivePlan,
    instances: Mapping[str, ModelInstanceIndex],
) -> Optional[JointControllers]:
    """The controllers of ``plan`` wired to ``plant`` (None: no model has any)."""
    if not plan.configs:
        return None
    system = builder.AddSystem(JointControllers(plant, plan, instances))
    builder.Connect(plant.get_state_output_port(), system.get_input_port(0))
    for model in plan.configs:
        builder.Connect(
            system.GetOutputPort(f"{model}.desired_state"),
            plant.get_desired_state_input_port(instances[model]),
        )
        builder.Connect(
            system.GetOutputPort(f"{model}.feedforward"), plant.get_actuation_input_port(instances[model])
        )
    return system
