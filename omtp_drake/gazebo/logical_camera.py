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

Which models it publishes, and how it names them, are the plugin's rules
(:class:`PluginListing`, from the camera's ``plugin_names.camera_listings`` entry, which
:func:`omtp_drake.launch.plugins.camera_listing` reads from the student's ``<plugin>``):

- with ``known_model_types`` or ``known_model_names``, only a model whose type
  (:func:`~omtp_drake.cell.gazebo_models.model_type`, ARIAC's ``DetermineModelType``) is a
  known type, or whose name (after its last ``|``) is a known name, is published; nested
  models too, each by its own type and name;
- a published model's type is its type, or ``model`` with ``anonymize_models``; its tf
  frame, child of ``<camera>_frame``, is ``<model_frame_prefix><name>_frame`` (the prefix
  by default ``<camera>_``; with ``anonymize_models`` the name is ``model_<id>``, ``<id>``
  ARIAC's ``DetermineModelId``: ``object_3`` -> ``model_3``). Nested models get their type
  (never anonymized) and no frame, as the plugin's;
- a plugin whose Load stopped (a ``<known_model_types>`` without ``<type>``) advertises
  nothing;
- for a published model of type ``agv1`` or ``agv2`` (ARIAC's AGVs), the plugin also
  broadcasts its kit tray's tf frame ``<model_frame_prefix>kit_tray_1_frame`` (``_2``)
  under the model's frame, 0.15 m along its y and 0.75 m up (:data:`X_AGV_KIT_TRAY`); the
  message does not list it. The plugin puts its noise on the tray there, not on the AGV
  ("too much noise by the time the tray pose is extrapolated"): the AGV is published at
  its true pose, and the camera's noise draw for it moves the tray in the AGV's frame.
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING, Optional

from pydrake.math import RigidTransform

from omtp_drake.cell.camera_image import DetectedModel, LogicalCameraImage
from omtp_drake.cell.gazebo_camera import GazeboCameraView
from omtp_drake.cell.gazebo_models import model_type
from omtp_drake.cell.logical_camera import add_pose_noise
from omtp_drake.gazebo.schedule import Publication
from omtp_drake.scenario.plugin_names import CameraListing

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station
    from omtp_drake.script import Cell

#: The lecture's single-camera topic.
SINGLE_CAMERA_TOPIC = "/omtp/logical_camera"
#: The default single camera when the scenario's task names none.
DEFAULT_SINGLE_CAMERA = "logical_camera_1"
#: The plugin's AGV types (ARIAC's) and the kit tray each carries: for an AGV it
#: publishes, the plugin also broadcasts ``<prefix><tray>_frame`` under the AGV's frame.
KIT_TRAYS = {"agv1": "kit_tray_1", "agv2": "kit_tray_2"}
#: The kit tray's pose in its AGV's frame (the plugin's ``kitTrayToAgv``).
X_AGV_KIT_TRAY = RigidTransform([0.0, 0.15, 0.75])


def noisy_tray(X_CM: RigidTransform, X_CM_true: RigidTransform) -> RigidTransform:
    """The kit tray's pose in its AGV's frame with the noise the camera drew for the AGV
    (``X_CM`` against ``X_CM_true``) put on it, as the plugin's ``AddNoise`` of the tray
    (:func:`~omtp_drake.cell.logical_camera.add_pose_noise`: offsets added, the rotation's
    perturbation composed on the right)."""
    R_pert = X_CM_true.rotation().inverse() @ X_CM.rotation()
    return add_pose_noise(X_AGV_KIT_TRAY, X_CM.translation() - X_CM_true.translation(), R_pert)


def single_camera(cell: Cell) -> Optional[str]:
    """The camera behind ``/omtp/logical_camera``: the task's, else logical_camera_1."""
    cameras = set(cell.station.cameras)
    task = getattr(cell.scenario, "task", None)
    name = getattr(task, "camera", None) if task is not None else None
    if name in cameras:
        return name
    return DEFAULT_SINGLE_CAMERA if DEFAULT_SINGLE_CAMERA in cameras else None


def model_id(name: str) -> str:
    """ARIAC's ``DetermineModelId``: the name after its last ``|``; when it ends in
    ``_<digits>`` after at least two characters, those digits (``object_3`` -> ``3``)."""
    name = name.rsplit("|", 1)[-1]
    match = re.fullmatch(r".{2,}_(\d*)", name)
    return match.group(1) if match is not None else name


class PluginListing:
    """How the logical camera ``camera``'s plugin publishes a model (see the module doc)."""

    def __init__(self, camera: str, listing: CameraListing):
        self._listing = listing
        self._prefix = listing.frame_prefix(camera)
        self._filtered = listing.known_model_types is not None or listing.known_model_names is not None
        self._types = set(listing.known_model_types or ())
        self._names = set(listing.known_model_names or ())

    def publishes(self, name: str) -> bool:
        """Whether the plugin publishes the model ``name`` (its ``ModelToPublish``)."""
        if not self._listing.advertised:
            return False
        known = model_type(name) in self._types or name.rsplit("|", 1)[-1] in self._names
        return known or not self._filtered

    def model(self, name: str, X_CM: RigidTransform, X_CM_true: RigidTransform) -> Optional[DetectedModel]:
        """The published model ``name`` at ``X_CM`` (the camera's noise on it; ``X_CM_true``
        without), or None: the plugin does not publish it."""
        if not self.publishes(name):
            return None
        kind = model_type(name)
        tray = KIT_TRAYS.get(kind)
        trays: tuple[tuple[str, RigidTransform], ...] = ()
        if tray:  # an AGV's kit tray: a tf frame under the AGV's, not in the message
            trays = ((f"{self._prefix}{tray}_frame", noisy_tray(X_CM, X_CM_true)),)
            X_CM = X_CM_true
        if self._listing.anonymize_models:
            frame = f"{self._prefix}model_{model_id(name)}_frame"
            return DetectedModel("", "model", X_CM, frame=frame, tf_children=trays)
        trimmed = name.rsplit("|", 1)[-1]
        return DetectedModel(trimmed, kind, X_CM, frame=f"{self._prefix}{trimmed}_frame", tf_children=trays)

    def nested(self, name: str, X_CM: RigidTransform) -> Optional[DetectedModel]:
        return DetectedModel("", model_type(name), X_CM) if self.publishes(name) else None


def camera_view(station: Station, camera: str) -> GazeboCameraView:
    """The course plugin's view of ``station``'s camera ``camera`` (what its topic, and tf's
    frames, list), by the rules of its plugin in the station's scenario."""
    listing = station.scenario.plugin_names.camera_listing(camera)
    return GazeboCameraView(station, camera, PluginListing(camera, listing))


def camera_views(cell: Cell) -> dict[str, GazeboCameraView]:
    """Camera -> the course plugin's view of it (:func:`camera_view`)."""
    return {name: camera_view(cell.station, name) for name in cell.station.cameras}


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
        if topics.camera_listing(name).advertised
    ]
    single = single_camera(cell)
    if single is not None and topics.camera_listing(single).advertised:
        out.append(
            Publication(
                SINGLE_CAMERA_TOPIC, LogicalCameraImage, NewImages(cell, views[single]), plugin=single
            )
        )
    return out
