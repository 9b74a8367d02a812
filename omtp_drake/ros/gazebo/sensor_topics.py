"""The cell's sensor topics, as the course's Gazebo plugins publish them.

- ``/omtp/<camera>`` and ``/omtp/logical_camera``: the logical camera plugin's
  (:mod:`omtp_drake.gazebo.logical_camera`: which cameras, when, which models) as
  ``omtp_gazebo/LogicalCameraImage``; the single camera's frame tf also knows as
  ``logical_camera_frame``.
- ``/break_beam_sensor`` and ``/break_beam_sensor_change`` (``omtp_gazebo/Proximity``),
  named after the beam's sensor as its plugin names them: the first at every sample
  of the beam (its rate, 10 Hz), the second only when ``object_detected`` changes
  (the plugin starts at "not detected", so the first message is the first
  detection). Both are latched: a late subscriber gets the last message at once.
  Stamped with the sample's time; ``frame_id`` is the plugin's ``<sensor>_frame``;
  ``min_range`` and ``max_range`` are the beam's range.
- ``/gripperN/state`` (``omtp_gazebo/VacuumGripperState``) for the gripper whose
  plugin is ``gripperN``: ``enabled`` and ``attached``, once per tick of the cell
  (the course's plugin publishes at every physics step, 1 kHz).

The cell's sources are polled between ticks; a latched one is polled even with no
subscriber, so that its last message is there for the next one.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from omtp_drake.ros.comm._core import GazeboCameraView, Publication, logical_camera_publications
from omtp_drake.ros.comm.interfaces import LogicalCameraImage, Model, Proximity, VacuumGripperState
from omtp_drake.ros.comm.messages import Header, Message, Time
from omtp_drake.ros.gazebo.cell_services import gripper_plugins
from omtp_drake.ros.tf.convert import pose_msg

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import BreakBeam, Cell

#: The lecture's single camera's frame in tf.
SINGLE_CAMERA_FRAME = "logical_camera_frame"


#: The break beam's sensor, after which its plugin names its topics and frame.
BREAK_BEAM_SENSOR = "break_beam_sensor"


class Source:
    """A topic the cell publishes: ``poll()`` returns the (stamp, message) pairs
    that are new since the last poll; ``msg_class`` is its type; ``latch``: the
    last message goes to every new subscriber."""

    msg_class: Any
    latch: bool = False

    def poll(self) -> list[tuple[float, Any]]:
        raise NotImplementedError


class CameraSource(Source):
    """A logical camera's topic: the plugin layer's publication as the course's message."""

    msg_class = LogicalCameraImage

    def __init__(self, cell: Cell, publication: Publication):
        self._cell = cell
        self._poll = publication.poll

    def poll(self) -> list[tuple[float, Any]]:
        return [(image.time, camera_message(image)) for image in self._poll(self._cell.time)]


def camera_message(image: Any) -> Message:
    """A logical camera image as the course's message (types and poses in the camera frame)."""
    return LogicalCameraImage(
        models=[Model(type=m.type, pose=pose_msg(m.X_CM)) for m in image.models], pose=pose_msg(image.X_WC)
    )


class BreakBeamSource(Source):
    """One of the beam's two topics: every sample, or (``changes_only``) the changes."""

    msg_class = Proximity
    latch = True

    def __init__(self, cell: Cell, beam: BreakBeam, changes_only: bool):
        self._cell = cell
        self._rate = beam.rate_hz
        self._range = beam.range
        self._changes_only = changes_only
        self._sample = -1
        self._detected = False

    def poll(self) -> list[tuple[float, Any]]:
        sample = math.floor(self._cell.time * self._rate + 1e-6)
        if sample <= self._sample:
            return []
        self._sample = sample
        detected = bool(self._cell.break_beam())
        changed, self._detected = detected != self._detected, detected
        if self._changes_only and not changed:
            return []
        stamp = sample / self._rate
        header = Header(stamp=Time(stamp), frame_id=f"{BREAK_BEAM_SENSOR}_frame")
        message = Proximity(
            header=header, object_detected=detected, min_range=self._range[0], max_range=self._range[1]
        )
        return [(stamp, message)]


class GripperStateSource(Source):
    """A gripper's ``enabled`` and ``attached``, once per poll."""

    msg_class = VacuumGripperState

    def __init__(self, cell: Cell, robot: str):
        self._gripper = cell.gripper(robot)
        self._cell = cell

    def poll(self) -> list[tuple[float, Any]]:
        state = self._gripper.state()
        return [(self._cell.time, VacuumGripperState(enabled=state.enabled, attached=state.attached))]


def cell_sources(cell: Cell, views: dict[str, GazeboCameraView]) -> dict[str, Source]:
    """Topic name -> source of every sensor topic of ``cell`` (``views``: the logical
    cameras' views, :func:`omtp_drake.gazebo.logical_camera.camera_views`)."""
    sources: dict[str, Source] = {
        p.topic: CameraSource(cell, p) for p in logical_camera_publications(cell, views)
    }
    beam = cell.station.break_beam
    if beam is not None:
        sources[f"/{BREAK_BEAM_SENSOR}"] = BreakBeamSource(cell, beam, changes_only=False)
        sources[f"/{BREAK_BEAM_SENSOR}_change"] = BreakBeamSource(cell, beam, changes_only=True)
    for robot, plugin in gripper_plugins(cell).items():
        sources[f"/{plugin}/state"] = GripperStateSource(cell, robot)
    return sources
