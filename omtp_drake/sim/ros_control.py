"""ros_control / ros2_control on a running cell: the controllers' rules, transport-neutral.

The cell drives the joints (:mod:`omtp_drake.cell.joint_controllers`); this module
is what a controller does with what it is sent, and what it publishes, as
ros_controllers and ros2_controllers do. The ROS 1 shim and the ROS 2 node only give
these their topic names and message types.

- A **joint state** controller (``JointStateController``, ``JointStateBroadcaster``)
  publishes every hardware joint's position, velocity and effort at its rate
  (:meth:`RosControl.period`): ROS 1's ``publish_rate``; ROS 2's ``update_rate`` of the
  controller, else the controller manager's (100 Hz by default), and never faster
  than the physics updates (one per plant step), as the controller manager runs in
  Gazebo's update.
- A **trajectory** controller follows a trajectory (:meth:`RosControl.follow`): it
  must name each of the controller's joints once (in any order), its points' times
  must increase, each point has one position per joint (velocities and accelerations
  none or one per joint). It starts at ``header.stamp`` (now when zero); points
  already past are dropped; the joints go from where the controller's command has
  them now to the first point, then on through the others
  (:mod:`omtp_drake.cell.joint_splines`), and hold the last. A trajectory without
  points stops the joints where they are commanded now. A new trajectory replaces
  the one playing. A refused trajectory is a ConfigError (the transports log it,
  as the controllers do, and keep what played).
- A trajectory controller's **state** (:meth:`RosControl.controller_state`: the command
  now, the joints measured, their difference) is published every
  :meth:`RosControl.state_period`: on ROS 1 at its ``state_publish_rate`` (50 Hz by
  default, 0: never), never faster than its updates; on ROS 2 at each of its updates
  (its :meth:`~RosControl.period`), as joint_trajectory_controller does since Iron
  (ros2_controllers #520 removed Humble's ``state_publish_rate``: a YAML's is ignored).
- A **forward** controller (``JointGroupPositionController``, ``JointPositionController``,
  ``ForwardCommandController``...) takes one value per joint: a position (held), a
  velocity or an effort, by its type.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from pydrake.systems.framework import Context

from omtp_drake.cell.joint_controllers import Command, JointControllers
from omtp_drake.cell.joint_splines import JointSpline, Waypoint
from omtp_drake.errors import ConfigError
from omtp_drake.scenario.ros_control import ControllerConfig, RosControlConfig
from omtp_drake.sim.trajectory_request import RequestPoint, TrajectoryRequest

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

#: ros2_control's controller manager rate when its YAML sets none (Hz).
ROS2_DEFAULT_UPDATE_RATE = 100.0


class PastTrajectoryError(ConfigError):
    """Every point of a trajectory is already past (the action's ``OLD_HEADER_TIMESTAMP``)."""


class JointNamesError(ConfigError):
    """A trajectory's joints are not the controller's (the action's ``INVALID_JOINTS``)."""


@dataclass(frozen=True)
class Controller:
    """A started controller of a model: the model's set-up and the controller's."""

    model: str
    setup: RosControlConfig
    config: ControllerConfig

    @property
    def name(self) -> str:
        return self.config.name

    @property
    def namespace(self) -> str:
        """The controller manager's namespace (``/`` or ``/robot``)."""
        return "/" + self.setup.namespace.strip("/") if self.setup.namespace.strip("/") else "/"


@dataclass(frozen=True)
class JointStateSample:
    """What a joint state controller publishes: names and per-joint values."""

    stamp: float
    names: tuple[str, ...]
    position: tuple[float, ...]
    velocity: tuple[float, ...]
    effort: tuple[float, ...]


@dataclass(frozen=True)
class ControllerStateSample:
    """What a trajectory controller's state topic carries: per joint, the ``reference`` its
    command asks now (ROS 1: ``desired``), the ``feedback`` measured (ROS 1: ``actual``)."""

    stamp: float
    joints: tuple[str, ...]
    reference_position: tuple[float, ...]
    reference_velocity: tuple[float, ...]
    feedback_position: tuple[float, ...]
    feedback_velocity: tuple[float, ...]

    @property
    def error_position(self) -> tuple[float, ...]:
        """Reference minus feedback."""
        return tuple(r - f for r, f in zip(self.reference_position, self.feedback_position))

    @property
    def error_velocity(self) -> tuple[float, ...]:
        return tuple(r - f for r, f in zip(self.reference_velocity, self.feedback_velocity))


class Periodic:
    """Due at every multiple of ``period`` s of simulated time (the first due at 0)."""

    def __init__(self, period: float):
        self.period = float(period)
        self._next = 0.0

    def due(self, now: float) -> bool:
        if now < self._next - 1e-9:
            return False
        self._next = (math.floor(now / self.period + 1e-9) + 1) * self.period
        return True


class RosControl:
    """The started controllers of ``station``'s models (see the module doc)."""

    def __init__(self, station: Station):
        self._station = station
        system = station.joint_controllers
        self._system: JointControllers | None = system
        self.controllers: list[Controller] = []
        if system is not None:
            for model, setup in system.configs.items():
                self.controllers += [Controller(model, setup, c) for c in setup.controllers]

    def of_kind(self, kind: str) -> list[Controller]:
        return [c for c in self.controllers if c.config.kind == kind]

    @property
    def system(self) -> JointControllers:
        if self._system is None:
            raise ConfigError("no model of the cell has a gazebo_ros_control or gazebo_ros2_control plugin")
        return self._system

    def period(self, controller: Controller) -> float:
        """Seconds between two joint state messages of ``controller``."""
        step = float(self._station.scenario.plant_config.time_step)
        rate = controller.config.publish_rate
        if rate <= 0:
            rate = controller.setup.update_rate
        if rate <= 0 and controller.setup.plugin == "gazebo_ros2_control":
            rate = ROS2_DEFAULT_UPDATE_RATE
        return max(1.0 / rate, step) if rate > 0 else step

    def state_period(self, controller: Controller) -> float | None:
        """Seconds between two state messages of ``controller`` (a trajectory controller),
        None when it publishes none (see the module doc)."""
        if controller.setup.plugin == "gazebo_ros2_control":
            return self.period(controller)
        rate = controller.config.state_publish_rate
        return max(1.0 / rate, self.period(controller)) if rate > 0 else None

    def controller_state(self, root_context: Context, controller: Controller) -> ControllerStateSample:
        """``controller``'s state now (a trajectory controller's)."""
        joints = tuple(controller.config.joints)
        q_d, v_d = self.desired(root_context, controller)
        q, v = self.system.measured(root_context, controller.model, joints)
        values = (tuple(map(float, x)) for x in (q_d, v_d, q, v))
        return ControllerStateSample(root_context.get_time(), joints, *values)

    def joint_state(self, root_context: Context, controller: Controller) -> JointStateSample:
        joints = controller.config.joints
        q, v = self.system.measured(root_context, controller.model, joints)
        plant = self._station.plant
        instance = plant.GetModelInstanceByName(controller.model)
        effort = plant.get_net_actuation_output_port(instance).Eval(plant.GetMyContextFromRoot(root_context))
        order = self.system.actuated_joints(controller.model)
        efforts = tuple(float(effort[order.index(j)]) if j in order else 0.0 for j in joints)
        return JointStateSample(
            root_context.get_time(), tuple(joints), tuple(map(float, q)), tuple(map(float, v)), efforts
        )

    def follow(self, root_context: Context, controller: Controller, request: TrajectoryRequest) -> Command:
        """``controller`` follows ``request`` from now (ConfigError: refused, see the module doc);
        returns the command it plays."""
        config = controller.config
        if config.kind != "trajectory":
            raise ConfigError(f"{config.name} ({config.type}) takes no trajectory")
        now = root_context.get_time()
        q_now, v_now = self.system.desired(root_context, controller.model, config.name)
        if not request.points:
            return self._set(root_context, controller, JointSpline.hold(q_now, now))
        order = _joint_order(config, request.joint_names)
        start = request.stamp if request.stamp > 0 else now
        points = [Waypoint(now, tuple(map(float, q_now)), tuple(map(float, v_now)), (0.0,) * len(q_now))]
        previous = -math.inf
        for k, point in enumerate(request.points):
            _check_point(config, k, point, len(order), previous)
            previous = point.time_from_start
            t = start + point.time_from_start
            if t <= now:
                continue
            points.append(
                Waypoint(
                    t,
                    tuple(point.positions[i] for i in order),
                    tuple(point.velocities[i] for i in order) if point.velocities else None,
                    tuple(point.accelerations[i] for i in order) if point.accelerations else None,
                )
            )
        if len(points) == 1:
            raise PastTrajectoryError(f"{config.name}: every point of the trajectory is in the past; dropped")
        return self._set(root_context, controller, JointSpline.through(points))

    def forward(self, root_context: Context, controller: Controller, values: Sequence[float]) -> None:
        """``controller`` (a forward controller) gets ``values``, one per joint."""
        config = controller.config
        if config.kind != "forward":
            raise ConfigError(f"{config.name} ({config.type}) takes no forwarded command")
        if len(values) != len(config.joints):
            raise ConfigError(
                f"{config.name}: dimension of command ({len(values)}) does not match number of joints "
                f"({len(config.joints)}); not executing"
            )
        if not all(math.isfinite(v) for v in values):
            raise ConfigError(f"{config.name}: a command value is not finite: {list(values)}")
        values = tuple(float(v) for v in values)
        joints = tuple(config.joints)
        if config.command == "position":
            command = Command(joints, spline=JointSpline.hold(values, root_context.get_time()))
        elif config.command == "velocity":
            command = Command(joints, velocities=values)
        else:
            command = Command(joints, efforts=values)
        self.system.command(root_context, controller.model, config.name, command)

    def _set(self, root_context: Context, controller: Controller, spline: JointSpline) -> Command:
        command = Command(tuple(controller.config.joints), spline=spline, tag=next(self.system.tags))
        self.system.command(root_context, controller.model, controller.name, command)
        return command

    def playing(self, root_context: Context, controller: Controller) -> Command:
        """The command ``controller`` plays now."""
        return self.system.command_of(root_context, controller.model, controller.name)

    def stop(self, root_context: Context, controller: Controller) -> None:
        """``controller``'s joints hold where they are commanded now (a cancelled or aborted goal)."""
        q, _ = self.desired(root_context, controller)
        self._set(root_context, controller, JointSpline.hold(q, root_context.get_time()))

    def desired(self, root_context: Context, controller: Controller) -> tuple[np.ndarray, np.ndarray]:
        """(positions, velocities) ``controller`` commands now (a trajectory controller's state)."""
        return self.system.desired(root_context, controller.model, controller.name)


def _joint_order(config: ControllerConfig, names: Sequence[str]) -> list[int]:
    """For each joint of the controller, its index in the trajectory's ``names``."""
    unknown = [n for n in names if n not in config.joints]
    if unknown:
        raise JointNamesError(
            f"{config.name}: joint {unknown[0]!r} of the trajectory is not one of the controller's: "
            f"{', '.join(config.joints)}"
        )
    if len(set(names)) != len(names) or len(names) != len(config.joints):
        raise JointNamesError(
            f"{config.name}: the trajectory must name each of the controller's joints once "
            f"({', '.join(config.joints)}), got {list(names)}"
        )
    return [list(names).index(j) for j in config.joints]


def _check_point(config: ControllerConfig, k: int, point: RequestPoint, n: int, previous: float) -> None:
    where = f"{config.name}: point {k}"
    if len(point.positions) != n:
        raise ConfigError(f"{where} has {len(point.positions)} positions for {n} joints")
    for key in ("velocities", "accelerations"):
        size = len(getattr(point, key))
        if size not in (0, n):
            raise ConfigError(f"{where} has {size} {key} for {n} joints (give none or one per joint)")
    values = (*point.positions, *point.velocities, *point.accelerations, point.time_from_start)
    if not all(math.isfinite(v) for v in values):
        raise ConfigError(f"{where} holds a value that is not finite")
    if point.time_from_start <= previous:
        raise ConfigError(f"{where}: time_from_start must increase from point to point")
