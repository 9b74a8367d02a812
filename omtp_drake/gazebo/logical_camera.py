"""The course's logical camera plugin (``omtp_gazebo``'s ``ROSLogicalCameraPlugin``): what
each logical camera reports, when, on which topic.

- ``/omtp/<camera>`` for every logical camera (the plugin's ``robotNamespace`` ``omtp``
  and the camera model's name; a student's ``robotNamespace`` and ``image_topic_ros``, read
  once into the scenario's ``plugin_names``), and ``/omtp/logical_camera``, the lecture's single
  camera (:func:`single_camera`);
- one message per new image of the camera (its rate), stamped with the image's time:
  the camera's pose in the world and every Gazebo model in view with its origin's pose
  in the camera frame, as the course's plugin lists them
  (:class:`~omtp_drake.cell.gazebo_camera.GazeboCameraView`: robots, pedestals, bins, the
  belt, parts...). The message is the cell's
  :class:`~omtp_drake.cell.camera_image.LogicalCameraImage`; a transport gives it its type.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Optional

from omtp_drake.cell.camera_image import LogicalCameraImage
from omtp_drake.cell.gazebo_camera import GazeboCameraView
from omtp_drake.gazebo.schedule import Publication

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The lecture's single-camera topic.
SINGLE_CAMERA_TOPIC = "/omtp/logical_camera"
#: The default single camera when the scenario's task names none.
DEFAULT_SINGLE_CAMERA = "logical_camera_1"


def single_camera(cell: Cell) -> Optional[str]:
    """The camera behind ``/omtp/logical_camera``: the task's, else logical_camera_1."""
    cameras = set(cell.station.cameras)
    task = getattr(cell.scenario, "task", None)
    name = getattr(task, "camera", None) if task is not None else None
    if name in cameras:
        return name
    return DEFAULT_SINGLE_CAMERA if DEFAULT_SINGLE_CAMERA in cameras else None


def camera_views(cell: Cell) -> dict[str, GazeboCameraView]:
    """Camera -> the course plugin's view of it (what its topic, and tf's frames, list)."""
    return {name: GazeboCameraView(cell.station, name) for name in cell.station.cameras}


class NewImages:
    """A camera's images, each once: a poll returns the image when it is new."""

    def __init__(self, cell: Cell, view: GazeboCameraView):
        self._cell = cell
        self._view = view
        self._last = -math.inf

    def __call__(self, t: float) -> list[LogicalCameraImage]:
        image = self._view.image(self._cell.runtime.context)
        if not math.isfinite(image.time) or image.time <= self._last:
            return []
        self._last = image.time
        return [image]


def logical_camera_publications(cell: Cell, views: dict[str, GazeboCameraView]) -> list[Publication]:
    """The topics above of ``cell``'s cameras, from ``views`` (:func:`camera_views`; a
    transport shares them with its tf)."""
    topics = cell.scenario.plugin_names
    out = [
        Publication(topics.camera_topic(name), LogicalCameraImage, NewImages(cell, view), plugin=name)
        for name, view in views.items()
    ]
    single = single_camera(cell)
    if single is not None:
        out.append(
            Publication(
                SINGLE_CAMERA_TOPIC, LogicalCameraImage, NewImages(cell, views[single]), plugin=single
            )
        )
    return out
