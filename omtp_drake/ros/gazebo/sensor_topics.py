"""The cell's logical camera topics, as the course's plugin publishes them.

- ``/omtp/<camera>`` and ``/omtp/logical_camera``: the logical camera plugin's
  (:mod:`omtp_drake.gazebo.logical_camera`: which cameras, when, which models) as
  ``omtp_gazebo/LogicalCameraImage``; the single camera's frame tf also knows as
  ``logical_camera_frame``.

The break beam's and the grippers' topics are the plugin layer's
(:mod:`omtp_drake.gazebo.proximity_ray`, :mod:`omtp_drake.gazebo.vacuum_gripper`), on the
graph with every other plugin's (:mod:`omtp_drake.ros.gazebo.plugin_topics`).

The cell's sources are polled between ticks; a latched one is polled even with no
subscriber, so that its last message is there for the next one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from omtp_drake.ros.comm._core import GazeboCameraView, Publication, logical_camera_publications
from omtp_drake.ros.comm.interfaces import LogicalCameraImage, Model
from omtp_drake.ros.comm.messages import Message
from omtp_drake.ros.tf.convert import pose_msg

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell

#: The lecture's single camera's frame in tf.
SINGLE_CAMERA_FRAME = "logical_camera_frame"


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


def cell_sources(cell: Cell, views: dict[str, GazeboCameraView]) -> dict[str, Source]:
    """Topic name -> source of every logical camera topic of ``cell`` (``views``: the logical
    cameras' views, :func:`omtp_drake.gazebo.logical_camera.camera_views`)."""
    sources: dict[str, Source] = {
        p.topic: CameraSource(cell, p) for p in logical_camera_publications(cell, views)
    }
    return sources
