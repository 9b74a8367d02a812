"""The cell's sensor topics, as the course's Gazebo plugins publish them.

- ``/omtp/<camera>`` for every logical camera (``/omtp/logical_camera_1``...: the
  plugin's ``robotNamespace`` ``omtp`` and the camera model's name):
  ``omtp_gazebo/LogicalCameraImage`` at the camera's rate (one message per new
  image, published at the image's time), listing every Gazebo model in view as the
  course's plugin does (robots, pedestals, bins, the workcell, the belt, parts; see
  :mod:`omtp_drake.cell.gazebo_camera`); ``/omtp/logical_camera`` is the
  lecture's single camera: the scenario task's camera (else ``logical_camera_1``),
  whose frame tf also knows as ``logical_camera_frame``.
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
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.ros.comm._core import GazeboCameraView
from omtp_drake.ros.comm.interfaces import LogicalCameraImage, Model, Proximity, VacuumGripperState
from omtp_drake.ros.comm.messages import Header, Message, Time
from omtp_drake.ros.gazebo.cell_services import gripper_plugins
from omtp_drake.ros.tf.convert import pose_msg

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import BreakBeam, Cell

#: The lecture's single-camera topic and frame.
SINGLE_CAMERA_TOPIC = "/omtp/logical_camera"
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
    """A logical camera's topic: the course plugin's model list
    (:class:`~omtp_drake.cell.gazebo_camera.GazeboCameraView`), one message per new image."""

    msg_class = LogicalCameraImage

    def __init__(self, cell: Cell, view: GazeboCameraView):
        self._cell = cell
        self._view = view
        self._last = -math.inf

    def poll(self) -> list[tuple[float, Any]]:
        image = self._view.image(self._cell.runtime.context)
        if not math.isfinite(image.time) or image.time <= self._last:
            return []
        self._last = image.time
        return [(image.time, camera_message(image))]


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


def single_camera(cell: Cell) -> Optional[str]:
    """The camera behind ``/omtp/logical_camera``: the task's, else logical_camera_1."""
    cameras = set(cell.station.cameras)
    task = getattr(cell.scenario, "task", None)
    name = getattr(task, "camera", None) if task is not None else None
    if name in cameras:
        return name
    return "logical_camera_1" if "logical_camera_1" in cameras else None


def camera_views(cell: Cell) -> dict[str, GazeboCameraView]:
    """Camera -> the course plugin's view of it (what its topic and its tf frames list)."""
    return {name: GazeboCameraView(cell.station, name) for name in cell.station.cameras}


def cell_sources(cell: Cell, views: dict[str, GazeboCameraView]) -> dict[str, Source]:
    """Topic name -> source of every sensor topic of ``cell`` (``views``: :func:`camera_views`)."""
    sources: dict[str, Source] = {f"/omtp/{name}": CameraSource(cell, view) for name, view in views.items()}
    single = single_camera(cell)
    if single is not None:
        sources[SINGLE_CAMERA_TOPIC] = CameraSource(cell, views[single])
    beam = cell.station.break_beam
    if beam is not None:
        sources[f"/{BREAK_BEAM_SENSOR}"] = BreakBeamSource(cell, beam, changes_only=False)
        sources[f"/{BREAK_BEAM_SENSOR}_change"] = BreakBeamSource(cell, beam, changes_only=True)
    for robot, plugin in gripper_plugins(cell).items():
        sources[f"/{plugin}/state"] = GripperStateSource(cell, robot)
    return sources
