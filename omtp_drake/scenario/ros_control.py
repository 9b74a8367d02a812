"""A robot's ros_control / ros2_control set-up as typed settings: hardware joints and controllers.

ROS 1 (``gazebo_ros_control``): the URDF's ``<transmission>`` elements say which joints
the hardware has and by which interface they are commanded
(``hardware_interface/PositionJointInterface``, ``VelocityJointInterface``,
``EffortJointInterface``); a controllers YAML, loaded with ``rosparam`` and started by
``controller_manager``'s ``spawner``, says which controllers run. ROS 2
(``gazebo_ros2_control``): the ``<ros2_control>`` tag lists the joints with their command
and state interfaces and ``initial_value``\\ s; the plugin's ``<parameters>`` YAML holds
``controller_manager``'s ``update_rate`` and each controller's parameters.

:class:`RosControlConfig` is what the cell's joint-controller layer needs of either:
the joints, the update rate, and the started controllers (:class:`ControllerConfig`),
each of one :data:`CONTROLLER_TYPES` kind. ``validate(where)`` checks them once; the
reading lives in :mod:`omtp_drake.scenario.ros_control_parse`.
"""

import math
from dataclasses import dataclass, field
from typing import Optional

from omtp_drake.errors import MAX_RATE_HZ, ConfigError, UnknownNameError

#: The joint interfaces a command may drive.
INTERFACES = ("position", "velocity", "effort")
#: The controller kinds of the layer: joint states out, a trajectory followed, a command forwarded.
KINDS = ("joint_states", "trajectory", "forward")

#: Controller type -> (kind, the command interface; None: the YAML's ``command_interfaces``
#: or ``interface_name``), for the controller types of ros_controllers and ros2_controllers.
CONTROLLER_TYPES: dict[str, tuple[str, Optional[str]]] = {
    "joint_state_controller/JointStateController": ("joint_states", None),
    "joint_state_broadcaster/JointStateBroadcaster": ("joint_states", None),
    "position_controllers/JointTrajectoryController": ("trajectory", "position"),
    "velocity_controllers/JointTrajectoryController": ("trajectory", "velocity"),
    "effort_controllers/JointTrajectoryController": ("trajectory", "effort"),
    "joint_trajectory_controller/JointTrajectoryController": ("trajectory", None),
    "position_controllers/JointPositionController": ("forward", "position"),
    "velocity_controllers/JointVelocityController": ("forward", "velocity"),
    "effort_controllers/JointEffortController": ("forward", "effort"),
    "effort_controllers/JointPositionController": ("forward", "effort"),
    "position_controllers/JointGroupPositionController": ("forward", "position"),
    "velocity_controllers/JointGroupVelocityController": ("forward", "velocity"),
    "effort_controllers/JointGroupEffortController": ("forward", "effort"),
    "effort_controllers/JointGroupPositionController": ("forward", "effort"),
    "forward_command_controller/ForwardCommandController": ("forward", None),
}

#: Controller types that compute an effort from a PID on the position error (their gains needed).
PID_TYPES = (
    "effort_controllers/JointTrajectoryController",
    "velocity_controllers/JointTrajectoryController",
    "effort_controllers/JointPositionController",
    "effort_controllers/JointGroupPositionController",
)


@dataclass
class PidGains:
    """A joint's ``p``, ``i``, ``d`` and ``i_clamp`` (control_toolbox's PID)."""

    p: float = 0.0
    i: float = 0.0
    d: float = 0.0
    i_clamp: float = 0.0

    def validate(self, where: str) -> None:
        for key in ("p", "i", "d", "i_clamp"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value >= 0):
                raise ConfigError(f"{where}: {key} must be a finite number >= 0, got {value}")


@dataclass
class JointTolerance:
    """``constraints: <joint>: {trajectory, goal}``: allowed position errors (rad or m; 0: none)."""

    trajectory: float = 0.0
    goal: float = 0.0


@dataclass
class ControllerConfig:
    """One started controller: its name, type, joints and parameters."""

    name: str = ""
    type: str = ""
    joints: list[str] = field(default_factory=list)
    #: The command interface it writes (derived from the type, or the YAML's).
    interface: str = "position"
    #: joint_states: ``publish_rate`` (ROS 1) or ``update_rate`` (ROS 2; 0: the manager's rate).
    publish_rate: float = 0.0
    #: trajectory: ``state_publish_rate`` of its state topic (Hz).
    state_publish_rate: float = 50.0
    #: ``constraints``: ``goal_time`` (s), ``stopped_velocity_tolerance`` and per joint.
    goal_time: float = 0.0
    stopped_velocity_tolerance: float = 0.01
    tolerances: dict[str, JointTolerance] = field(default_factory=dict)
    #: ``gains`` (trajectory) or ``pid`` (single joint) of a controller computing effort.
    gains: dict[str, PidGains] = field(default_factory=dict)

    @property
    def kind(self) -> str:
        return CONTROLLER_TYPES[self.type][0]

    @property
    def command(self) -> str:
        """What a forwarded command means: a position for the PID controllers, else the
        interface's quantity."""
        return "position" if self.type in PID_TYPES else self.interface

    def validate(self, where: str) -> None:
        here = f"{where}: controller {self.name!r}"
        if self.type not in CONTROLLER_TYPES:
            raise UnknownNameError(f"type of {here}", self.type, CONTROLLER_TYPES)
        if self.interface not in INTERFACES:
            raise UnknownNameError(f"command interface of {here}", self.interface, INTERFACES)
        if self.kind != "joint_states" and not self.joints:
            raise ConfigError(f"{here} ({self.type}) has no joints")
        if len(set(self.joints)) != len(self.joints):
            raise ConfigError(f"{here} names a joint twice: {self.joints}")
        for key in ("publish_rate", "state_publish_rate"):
            value = getattr(self, key)
            if not (0 <= value <= MAX_RATE_HZ):
                raise ConfigError(f"{here}: {key} must be in [0, {MAX_RATE_HZ:g}] Hz, got {value}")
        if self.type == "joint_state_controller/JointStateController" and self.publish_rate <= 0:
            raise ConfigError(f"{here}: parameter 'publish_rate' not set (JointStateController needs it)")
        if self.type in PID_TYPES:
            missing = [j for j in self.joints if j not in self.gains]
            if missing:
                raise ConfigError(f"{here}: no p gain specified for pid of joint {missing[0]!r}")
        for joint, gains in self.gains.items():
            gains.validate(f"{here}: gains of {joint!r}")


@dataclass
class HardwareJoint:
    """A joint of the robot hardware: its command interfaces and its start position."""

    name: str = ""
    command_interfaces: list[str] = field(default_factory=lambda: ["position"])
    #: ``<state_interface name="position"><param name="initial_value">`` (None: the model's).
    initial_position: Optional[float] = None

    def validate(self, where: str) -> None:
        for interface in self.command_interfaces:
            if interface not in INTERFACES:
                raise UnknownNameError(
                    f"{where}: command interface of joint {self.name!r}", interface, INTERFACES
                )
        if self.initial_position is not None and not math.isfinite(self.initial_position):
            raise ConfigError(f"{where}: initial_value of {self.name!r} must be finite")


@dataclass
class RosControlConfig:
    """A model's ``gazebo_ros_control`` or ``gazebo_ros2_control`` plugin and what it runs."""

    #: ``gazebo_ros_control`` (ROS 1) or ``gazebo_ros2_control`` (ROS 2).
    plugin: str = "gazebo_ros_control"
    #: ``robotNamespace`` / ``<ros><namespace>``: the controller manager's namespace.
    namespace: str = "/"
    #: The controllers YAML the controllers were read from (named in errors).
    parameters: str = ""
    #: The controller manager's rate (Hz; 0: every physics update).
    update_rate: float = 0.0
    joints: list[HardwareJoint] = field(default_factory=list)
    #: The started controllers, in the order they were started.
    controllers: list[ControllerConfig] = field(default_factory=list)
    #: ROS 2: every controller the plugin's YAML declares (a launch's spawners activate some).
    declared: list[ControllerConfig] = field(default_factory=list)

    def joint(self, name: str) -> HardwareJoint:
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise UnknownNameError("hardware joint", name, [j.name for j in self.joints])

    def validate(self, where: str) -> None:
        if not 0 <= self.update_rate <= MAX_RATE_HZ:
            raise ConfigError(
                f"{where}: update_rate must be in [0, {MAX_RATE_HZ:g}] Hz, got {self.update_rate}"
            )
        for hardware in self.joints:
            hardware.validate(where)
        names = [j.name for j in self.joints]
        claimed: dict[str, str] = {}
        where = self.parameters or where
        for controller in self.declared:
            controller.validate(where)
        for controller in self.controllers:
            controller.validate(where)
            for joint in controller.joints:
                if joint not in names:
                    raise UnknownNameError(f"{where}: joint of controller {controller.name!r}", joint, names)
                if controller.kind == "joint_states":
                    continue
                if controller.interface not in self.joint(joint).command_interfaces:
                    raise ConfigError(
                        f"{where}: controller {controller.name!r} commands {joint!r} by its "
                        f"{controller.interface} interface, which the hardware lacks "
                        f"(has: {', '.join(self.joint(joint).command_interfaces)})"
                    )
                if joint in claimed:
                    raise ConfigError(
                        f"{where}: controllers {claimed[joint]!r} and {controller.name!r} both claim "
                        f"joint {joint!r} (resource conflict; start one of them)"
                    )
                claimed[joint] = controller.name
