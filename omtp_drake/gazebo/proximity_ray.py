"""The course's break beam (``omtp_gazebo``'s ``ROSProximityRayPlugin`` on the beam's ray
sensor): its two topics, when the cell has a beam.

- Names: the plugin's parameters as the student's file sets them (``robotNamespace``,
  ``output_state_topic``, ``output_change_topic``, ``frame_id``; by default after the ray
  sensor), read once into the scenario's ``plugin_names``; the course's xacro sets none of
  them: ``/break_beam_sensor`` and ``/break_beam_sensor_change``, in the frame
  ``break_beam_sensor_frame``.
- ``/break_beam_sensor``: one message per scan of the ray sensor (its rate, 10 Hz: the
  cell's beam, :class:`~omtp_drake.cell.conveyor.BreakBeam`), stamped with the scan's time.
- ``/break_beam_sensor_change``: the same message, only when ``object_detected`` changed
  (the plugin starts at "not detected", so the first one is the first detection).
- Both are latched (the plugin advertises them so): a late subscriber gets the last one.
- ``min_range`` and ``max_range`` are the beam's sensing range (m).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from omtp_drake.gazebo.schedule import Publication, Sampled

if TYPE_CHECKING:
    from omtp_drake.cell.conveyor import BreakBeam
    from omtp_drake.script import Cell


@dataclass(frozen=True)
class Proximity:
    """``omtp_gazebo/Proximity``."""

    stamp: float
    frame_id: str
    object_detected: bool
    min_range: float
    max_range: float


class Changes:
    """The messages of ``scans`` whose ``object_detected`` differs from the last one's
    (starting from "not detected")."""

    def __init__(self, scans: Sampled[Proximity]):
        self._scans = scans
        self._detected = False

    def __call__(self, t: float) -> list[Proximity]:
        out = []
        for message in self._scans(t):
            if message.object_detected != self._detected:
                self._detected = message.object_detected
                out.append(message)
        return out


def _scans(cell: Cell, beam: BreakBeam) -> Sampled[Proximity]:
    low, high = beam.range
    frame = cell.scenario.plugin_names.beam_frame_id

    def message(stamp: float) -> Proximity:
        return Proximity(stamp, frame, bool(cell.break_beam()), low, high)

    return Sampled(beam.rate_hz, message)


def beam_publications(cell: Cell) -> list[Publication]:
    """The beam's two topics (none without a beam)."""
    beam = cell.station.break_beam
    if beam is None:
        return []
    names = cell.scenario.plugin_names
    plugin = "break_beam_sensor_controller"
    return [
        Publication(names.beam_state_topic, Proximity, _scans(cell, beam), latched=True, plugin=plugin),
        Publication(
            names.beam_change_topic, Proximity, Changes(_scans(cell, beam)), latched=True, plugin=plugin
        ),
    ]
