"""The cell's ROS services, by the course's names (see the reference, section 9).

- ``/gripperN/control`` (``omtp_gazebo/VacuumGripperControl``): vacuum on or off
  for the robot whose gripper is ``vacuum_gripperN``.
- ``/spawn_object_once`` and ``/spawn_object_at_robot2`` (``std_srvs/Empty``): a
  part at the scenario's spawn point; the first exists when that point is
  nearest robot 1 (the belt), the second when it is nearest robot 2.
- ``/start_spawn``, ``/stop_spawn`` (``std_srvs/Empty``): the periodic spawner.
- ``/omtp/conveyor/control`` (``omtp_gazebo/ConveyorBeltControl``): belt power in
  [0, 100]; a power outside answers ``success: False`` and logs why.

A service exists only when the scenario has what it drives. A call takes the
session's ``service`` latency before its handler runs (:mod:`omtp_drake.ros.latency`).
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from omtp_drake.errors import OmtpError
from omtp_drake.ros.interfaces import (
    ConveyorBeltControl,
    EmptyService,
    ServiceType,
    VacuumGripperControl,
)

if TYPE_CHECKING:
    from omtp_drake.script import Cell

_log = logging.getLogger("rospy")


class ServiceFailure(Exception):
    """A service handler could not do what was asked (rospy's ServiceException)."""


@dataclass(frozen=True)
class Service:
    """A service of the cell: its type and the handler (request -> response)."""

    name: str
    type: type[ServiceType]
    handler: Callable[[Any], Any]


def _gripper_services(cell: Cell) -> list[Service]:
    services = []
    for robot in cell.station.grippers:
        gripper_name = cell.station.arm(robot).config.gripper
        match = re.fullmatch(r"vacuum_gripper(\d+)", gripper_name or "")
        if match is None:
            continue
        gripper = cell.gripper(robot)

        def control(request: Any, gripper: Any = gripper) -> Any:
            (gripper.on if request.enable else gripper.off)()
            return VacuumGripperControl._response_class(success=True)

        services.append(Service(f"/gripper{match.group(1)}/control", VacuumGripperControl, control))
    return services


def _spawn_services(cell: Cell) -> list[Service]:
    spawner = cell.scenario.spawner
    if spawner is None:
        return []
    robots = {r.name: np.asarray(r.xy, dtype=float) for r in cell.scenario.robots}
    xy = np.asarray(spawner.xyz[:2], dtype=float)
    nearest = min(robots, key=lambda name: float(np.linalg.norm(robots[name] - xy))) if robots else ""
    name = {"robot1": "/spawn_object_once", "robot2": "/spawn_object_at_robot2"}.get(nearest)

    def spawn(_request: Any) -> Any:
        try:
            part = cell.spawn_part()
        except OmtpError as e:
            raise ServiceFailure(str(e)) from None
        _log.info("spawned %s", part)
        return EmptyService._response_class()

    def switch(on: bool) -> Callable[[Any], Any]:
        def handler(_request: Any) -> Any:
            cell.runtime.auto_spawn = on
            return EmptyService._response_class()

        return handler

    services = [
        Service("/start_spawn", EmptyService, switch(True)),
        Service("/stop_spawn", EmptyService, switch(False)),
    ]
    if name is not None:
        services.append(Service(name, EmptyService, spawn))
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
    services = _gripper_services(cell) + _spawn_services(cell) + _conveyor_services(cell)
    return {s.name: s for s in services}
