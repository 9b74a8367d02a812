"""The cell's ROS services, by the course's names (see the reference, section 9).

- ``/gripperN/control`` (``omtp_gazebo/VacuumGripperControl``): vacuum on or off
  for the robot whose gripper is ``vacuum_gripperN``.
- The spawner's services: :mod:`omtp_drake.ros.gazebo.spawner`; Gazebo's own
  (``/gazebo/...``): :mod:`omtp_drake.ros.gazebo.ros_api`.
- ``/omtp/conveyor/control`` (``omtp_gazebo/ConveyorBeltControl``): belt power in
  [0, 100]; a power outside answers ``success: False`` and logs why.
- move_group's services (``/compute_ik``...): :mod:`omtp_drake.ros.moveit.node`.

A service exists only when the scenario has what it drives. A call takes the
session's ``service`` latency before its handler runs (:mod:`omtp_drake.ros.comm.latency`).
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm.interfaces import (
    ConveyorBeltControl,
    ServiceType,
    VacuumGripperControl,
)

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

_log = logging.getLogger("rospy")


class ServiceFailure(Exception):
    """A service handler could not do what was asked (rospy's ServiceException)."""


@dataclass(frozen=True)
class Service:
    """A service of the cell: its type and the handler (request -> response)."""

    name: str
    type: type[ServiceType]
    handler: Callable[[Any], Any]


def gripper_plugins(cell: Cell) -> dict[str, str]:
    """Robot -> the name of its gripper's plugin (``gripperN`` for ``vacuum_gripperN``),
    the namespace of the gripper's ``control`` service and ``state`` topic."""
    plugins = {}
    for robot in cell.station.grippers:
        match = re.fullmatch(r"vacuum_gripper(\d+)", cell.station.arm(robot).config.gripper or "")
        if match is not None:
            plugins[robot] = f"gripper{match.group(1)}"
    return plugins


def _gripper_services(cell: Cell) -> list[Service]:
    services = []
    for robot, plugin in gripper_plugins(cell).items():
        gripper = cell.gripper(robot)

        def control(request: Any, gripper: Any = gripper) -> Any:
            (gripper.on if request.enable else gripper.off)()
            return VacuumGripperControl._response_class(success=True)

        services.append(Service(f"/{plugin}/control", VacuumGripperControl, control))
    return services


def _conveyor_services(cell: Cell) -> list[Service]:
    if cell.station.conveyor is None:
        return []

    def control(request: Any) -> Any:
        power = request.state.power
        try:
            cell.set_conveyor_power(power)
        except OmtpError as e:
            _log.warning("/omtp/conveyor/control: %s", e)
            return ConveyorBeltControl._response_class(success=False)
        return ConveyorBeltControl._response_class(success=True)

    return [Service("/omtp/conveyor/control", ConveyorBeltControl, control)]


def cell_services(cell: Cell) -> dict[str, Service]:
    """Service name -> service, for everything ``cell``'s scenario has."""
    services = _gripper_services(cell) + _conveyor_services(cell)
    return {s.name: s for s in services}
