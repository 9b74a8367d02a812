"""The course's conveyor belt plugin (``omtp_gazebo``'s ``ROSConveyorBeltPlugin``): its
control service, when the cell has a belt.

- ``/omtp/conveyor/control``: the course's conveyor model sets ``<robot_namespace>`` to
  ``/omtp``, and the plugin's topic is ``conveyor/control``; a student's ``<topic>`` and
  ``<robot_namespace>`` are read once into the scenario's ``plugin_names``.
- The request's ``state.power`` is the belt's power, a percentage of its top speed in
  [0, :data:`MAX_POWER`]; the belt runs at it from the next step on. A power outside is
  refused and nothing changes: the course's plugin logs "Incorrect power value" and
  still answers ``success: true``; here the answer is ``success: false``, with the
  reason logged (logger ``gazebo``) and in the reply's line, so a caller can tell.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING

from omtp_drake.errors import OmtpError
from omtp_drake.gazebo.services import PluginService, ServiceReply

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The belt's full power (%).
MAX_POWER = 100.0

_log = logging.getLogger("gazebo")


@dataclass(frozen=True)
class ConveyorBeltControl:
    """``omtp_gazebo/ConveyorBeltControl``'s request: ``state.power`` (%)."""

    power: float


def conveyor_services(cell: Cell) -> list[PluginService]:
    """``/omtp/conveyor/control`` (or the file's name) when ``cell`` has a belt."""
    if cell.station.conveyor is None:
        return []
    service = cell.scenario.plugin_names.conveyor_control_service

    def control(request: ConveyorBeltControl) -> ServiceReply:
        try:
            cell.set_conveyor_power(request.power)
        except OmtpError as e:
            _log.warning("%s: %s", service, e)
            return ServiceReply(False, str(e))
        return ServiceReply(True, f"conveyor power {request.power:g}")

    return [PluginService(service, ConveyorBeltControl, control, plugin="conveyor_belt_plugin")]
