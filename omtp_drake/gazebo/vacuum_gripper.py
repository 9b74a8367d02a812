"""The course's vacuum gripper plugin (``omtp_gazebo``'s ``ROSVacuumGripperPlugin``): its
state topic and control service, for each arm whose gripper is ``vacuum_gripperN``.

- Names: the plugin's own parameters as the student's file sets them (``robot_namespace``,
  ``control_topic``, ``state_topic``), read once into the scenario's ``plugin_names``
  (:mod:`omtp_drake.scenario.plugin_names`). Without a file (a built-in scenario), the
  course's xacro's: it names the plugin ``gripperN`` and sets ``gripperN/control`` and
  ``gripperN/state`` (no robot namespace), so ``/gripperN/control`` and ``/gripperN/state``.
- ``/gripperN/state``: ``enabled`` (the vacuum is on) and ``attached`` (a part is held), at
  every world update of the plugin (the course's publishes at every physics step; here
  once per step of the transport), stamped with the update's time (the course's message
  has no header: the stamp is for a bag).
- ``/gripperN/control``: ``enable`` switches the vacuum on or off; the plugin always
  answers ``success: true`` (a part touching the cup then attaches by the cell's rule,
  :mod:`omtp_drake.cell.suction`). The reply's line says what it did and which part is held.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from omtp_drake.gazebo.schedule import Periodic, Publication
from omtp_drake.gazebo.services import PluginService, ServiceReply
from omtp_drake.scenario.plugin_names import GripperNames

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The plugin publishes its state at every world update: at every poll of the transport.
STATE_PERIOD = 0.0


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


def gripper_plugins(cell: Cell) -> dict[str, GripperNames]:
    """Robot -> its gripper plugin's names: as the scenario's ``plugin_names`` has them (read
    from the student's ``<plugin>``), else the course's (``gripperN`` for ``vacuum_gripperN``)."""
    plugins = {}
    for robot in cell.station.grippers:
        names = cell.scenario.plugin_names.gripper(robot, cell.station.arm(robot).config.gripper or "")
        if names is not None:
            plugins[robot] = names
    return plugins


class VacuumGripperPlugin:
    """The plugin of ``robot``'s gripper on ``cell``, under its ``names``."""

    def __init__(self, cell: Cell, robot: str, names: GripperNames):
        self._gripper = cell.gripper(robot)
        self.names = names
        self.name = names.plugin

    def state(self, t: float) -> VacuumGripperState:
        state = self._gripper.state()
        return VacuumGripperState(t, bool(state.enabled), bool(state.attached))

    def control(self, request: VacuumGripperControl) -> ServiceReply:
        self._gripper.on() if request.enable else self._gripper.off()
        held = f"; holding {self._gripper.part}" if self._gripper.attached else ""
        return ServiceReply(True, f"vacuum {'on' if request.enable else 'off'}{held}")

    def publication(self) -> Publication:
        """``/gripperN/state`` (or the file's ``state_topic``)."""
        return Publication(
            self.names.state_topic, VacuumGripperState, Periodic(STATE_PERIOD, self.state), plugin=self.name
        )

    def service(self) -> PluginService:
        """``/gripperN/control`` (or the file's ``control_topic``)."""
        return PluginService(self.names.control_service, VacuumGripperControl, self.control, plugin=self.name)


def vacuum_grippers(cell: Cell) -> list[VacuumGripperPlugin]:
    """The gripper plugins of ``cell``."""
    return [VacuumGripperPlugin(cell, robot, names) for robot, names in gripper_plugins(cell).items()]


def gripper_publications(cell: Cell) -> list[Publication]:
    """``/gripperN/state`` of every gripper plugin of ``cell``."""
    return [plugin.publication() for plugin in vacuum_grippers(cell)]


def gripper_services(cell: Cell) -> list[PluginService]:
    """``/gripperN/control`` of every gripper plugin of ``cell``."""
    return [plugin.service() for plugin in vacuum_grippers(cell)]
