"""The course's break beam (``omtp_gazebo``'s ``ROSProximityRayPlugin`` on the beam's ray
sensor): its two topics, when the cell has a beam.

- Names: after the sensor, as the plugin names them by default (the course's xacro sets
  no ``output_state_topic`` nor ``robotNamespace``): ``/break_beam_sensor`` and
  ``/break_beam_sensor_change``, in the frame ``break_beam_sensor_frame``.
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

#: The beam's ray sensor, after which the plugin names its topics and frame.
BREAK_BEAM_SENSOR = "break_beam_sensor"


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

    def message(stamp: float) -> Proximity:
        return Proximity(stamp, f"{BREAK_BEAM_SENSOR}_frame", bool(cell.break_beam()), low, high)

    return Sampled(beam.rate_hz, message)


def beam_publications(cell: Cell) -> list[Publication]:
    """The beam's two topics (none without a beam)."""
    beam = cell.station.break_beam
    if beam is None:
        return []
    topic = f"/{BREAK_BEAM_SENSOR}"
    plugin = f"{BREAK_BEAM_SENSOR}_controller"
    return [
        Publication(topic, Proximity, _scans(cell, beam), latched=True, plugin=plugin),
        Publication(f"{topic}_change", Proximity, Changes(_scans(cell, beam)), latched=True, plugin=plugin),
    ]
