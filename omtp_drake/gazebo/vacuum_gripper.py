"""The course's vacuum gripper plugin (``omtp_gazebo``'s ``ROSVacuumGripperPlugin``): its
state topic and control service, for each arm whose gripper is ``vacuum_gripperN``.

- Names: the course's xacro names the plugin ``gripperN`` and sets ``<control_topic>`` and
  ``<state_topic>`` to ``gripperN/control`` and ``gripperN/state`` (no robot namespace), so
  ``/gripperN/control`` and ``/gripperN/state``.
- ``/gripperN/state``: ``enabled`` (the vacuum is on) and ``attached`` (a part is held), at
  every world update of the plugin (the course's publishes at every physics step; here
  once per step of the transport), stamped with the update's time (the course's message
  has no header: the stamp is for a bag).
- ``/gripperN/control``: ``enable`` switches the vacuum on or off; the plugin always
  answers ``success: true`` (a part touching the cup then attaches by the cell's rule,
  :mod:`omtp_drake.cell.suction`). The reply's line says what it did and which part is held.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

from omtp_drake.gazebo.schedule import Periodic, Publication
from omtp_drake.gazebo.services import PluginService, ServiceReply

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The plugin publishes its state at every world update: at every poll of the transport.
STATE_PERIOD = 0.0
#: The course's gripper models, ``vacuum_gripperN``, and their plugins' names, ``gripperN``.
_GRIPPER_MODEL = re.compile(r"vacuum_gripper(\d+)")


@dataclass(frozen=True)
class VacuumGripperState:
    """``omtp_gazebo/VacuumGripperState`` (and the update's time)."""

    stamp: float
    enabled: bool
    attached: bool


@dataclass(frozen=True)
class VacuumGripperControl:
    """``omtp_gazebo/VacuumGripperControl``'s request."""

    enable: bool


def gripper_plugins(cell: Cell) -> dict[str, str]:
    """Robot -> the name of its gripper's plugin (``gripperN`` for ``vacuum_gripperN``),
    the namespace of the gripper's ``control`` service and ``state`` topic."""
    plugins = {}
    for robot in cell.station.grippers:
        match = _GRIPPER_MODEL.fullmatch(cell.station.arm(robot).config.gripper or "")
        if match is not None:
            plugins[robot] = f"gripper{match.group(1)}"
    return plugins


class VacuumGripperPlugin:
    """The plugin ``name`` (``gripperN``) of ``robot``'s gripper on ``cell``."""

    def __init__(self, cell: Cell, robot: str, name: str):
        self._gripper = cell.gripper(robot)
        self.name = name

    def state(self, t: float) -> VacuumGripperState:
        state = self._gripper.state()
        return VacuumGripperState(t, bool(state.enabled), bool(state.attached))

    def control(self, request: VacuumGripperControl) -> ServiceReply:
        self._gripper.on() if request.enable else self._gripper.off()
        held = f"; holding {self._gripper.part}" if self._gripper.attached else ""
        return ServiceReply(True, f"vacuum {'on' if request.enable else 'off'}{held}")

    def publication(self) -> Publication:
        """``/gripperN/state``."""
        return Publication(
            f"/{self.name}/state", VacuumGripperState, Periodic(STATE_PERIOD, self.state), plugin=self.name
        )

    def service(self) -> PluginService:
        """``/gripperN/control``."""
        return PluginService(f"/{self.name}/control", VacuumGripperControl, self.control, plugin=self.name)


def vacuum_grippers(cell: Cell) -> list[VacuumGripperPlugin]:
    """The gripper plugins of ``cell``."""
    return [VacuumGripperPlugin(cell, robot, name) for robot, name in gripper_plugins(cell).items()]


def gripper_publications(cell: Cell) -> list[Publication]:
    """``/gripperN/state`` of every gripper plugin of ``cell``."""
    return [plugin.publication() for plugin in vacuum_grippers(cell)]


def gripper_services(cell: Cell) -> list[PluginService]:
    """``/gripperN/control`` of every gripper plugin of ``cell``."""
    return [plugin.service() for plugin in vacuum_grippers(cell)]
