"""The cell's sensor topics, as the course's Gazebo plugins publish them.

- ``/omtp/<camera>`` for every logical camera (``/omtp/logical_camera_1``...):
  ``omtp_gazebo/LogicalCameraImage`` at the camera's rate (one message per new
  image, published at the image's time); ``/omtp/logical_camera`` is the
  lecture's single camera: the scenario task's camera (else ``logical_camera_1``),
  whose frame tf also knows as ``logical_camera_frame``.
- ``/omtp/break_beam`` and ``/omtp/break_beam_change`` (``omtp_gazebo/Proximity``):
  the beam's state whenever it changes (sampled at the beam's rate).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.ros.convert import pose_msg
from omtp_drake.ros.interfaces import LogicalCameraImage, Model, Proximity
from omtp_drake.ros.messages import Header, Time

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The lecture's single-camera topic and frame.
SINGLE_CAMERA_TOPIC = "/omtp/logical_camera"
SINGLE_CAMERA_FRAME = "logical_camera_frame"


class Source:
    """A topic the cell publishes: ``poll()`` returns the (stamp, message) pairs
    that are new since the last poll; ``msg_class`` is its type."""

    msg_class: Any

    def poll(self) -> list[tuple[float, Any]]:
        raise NotImplementedError


class CameraSource(Source):
    msg_class = LogicalCameraImage

    def __init__(self, cell: Cell, camera: str):
        self._camera = cell.camera(camera)
        self._last = -math.inf

    def poll(self) -> list[tuple[float, Any]]:
        image = self._camera.image()
        if not math.isfinite(image.time) or image.time <= self._last:
            return []
        self._last = image.time
        return [(image.time, camera_message(image))]


def camera_message(image: Any) -> LogicalCameraImage:
    """A logical camera image as the course's message (types and poses in the camera frame)."""
    return LogicalCameraImage(
        models=[Model(type=m.type, pose=pose_msg(m.X_CM)) for m in image.models], pose=pose_msg(image.X_WC)
    )


class BreakBeamSource(Source):
    msg_class = Proximity

    def __init__(self, cell: Cell):
        self._cell = cell
        self._last: Optional[bool] = None

    def poll(self) -> list[tuple[float, Any]]:
        detected = self._cell.break_beam()
        if detected == self._last:
            return []
        self._last = detected
        stamp = self._cell.time
        header = Header(stamp=Time(stamp), frame_id="break_beam_optical_link")
        return [(stamp, Proximity(header=header, object_detected=detected))]


def single_camera(cell: Cell) -> Optional[str]:
    """The camera behind ``/omtp/logical_camera``: the task's, else logical_camera_1."""
    cameras = set(cell.station.cameras)
    task = getattr(cell.scenario, "task", None)
    name = getattr(task, "camera", None) if task is not None else None
    if name in cameras:
        return name
    return "logical_camera_1" if "logical_camera_1" in cameras else None


def cell_sources(cell: Cell) -> dict[str, Source]:
    """Topic name -> source of every sensor topic of ``cell``."""
    sources: dict[str, Source] = {f"/omtp/{name}": CameraSource(cell, name) for name in cell.station.cameras}
    single = single_camera(cell)
    if single is not None:
        sources[SINGLE_CAMERA_TOPIC] = CameraSource(cell, single)
    if cell.station.break_beam is not None:
        sources["/omtp/break_beam"] = BreakBeamSource(cell)
        sources["/omtp/break_beam_change"] = BreakBeamSource(cell)
    return sources
