"""What the course's logical camera plugin publishes: every Gazebo model whose bounding box
meets the camera's frustum.

Gazebo's ``LogicalCameraSensor`` lists each model of the world (not the camera's own)
whose axis-aligned bounding box in the world (the union of its own links' collision
boxes) meets the view frustum, with the model origin's pose in the camera frame. A
model with no links of its own (the conveyor, whose links are in nested models) has an
empty box, which Gazebo 9's test never rejects, so every camera lists it (see
:attr:`~omtp_drake.cell.gazebo_models.GazeboModel.own_links`). The course's
``ROSLogicalCameraPlugin`` has no ``known_model_types`` filter, so it publishes them
all, each followed by its nested models (at their poses, without a visibility test of
their own). Models are named and ordered as in :mod:`omtp_drake.cell.gazebo_models`,
typed by :func:`~omtp_drake.cell.gazebo_models.model_type`.

Here a body's box is the world-aligned box of its geometry's bounding box (the same
boxes :class:`~omtp_drake.cell.logical_camera.LogicalCamera` tests), and the test of
the model's box against the frustum is exact (Gazebo's is the six face planes only,
which may also admit a box just off a frustum corner). The camera's own sample (its
time and the body poses then) is the moment of the list, so it is as stale as the
camera's image; a part the camera's image shows is reported at the pose the image has
for it (the camera's noise included).

This is the ROS image's list (``/omtp/logical_camera_N``); the Python layer's
:class:`~omtp_drake.cell.camera_image.LogicalCameraImage` keeps its own models.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional, Protocol

import numpy as np
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context

from omtp_drake.cell.body_geometry import body_geometries, bounding_box
from omtp_drake.cell.camera_image import DetectedModel, LogicalCameraImage
from omtp_drake.cell.frustum import FrustumOverlap
from omtp_drake.cell.gazebo_models import GazeboModel, gazebo_models, model_type
from omtp_drake.cell.logical_camera import CameraSample

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station


class ModelListing(Protocol):
    """How a camera's plugin publishes a model in view (None: it does not): the plugin
    layer's rules (:mod:`omtp_drake.gazebo.logical_camera`)."""

    def model(self, name: str, X_CM: RigidTransform, X_CM_true: RigidTransform) -> Optional[DetectedModel]:
        """``X_CM``: the model's pose with the camera's noise; ``X_CM_true``: without."""

    def nested(self, name: str, X_CM: RigidTransform) -> Optional[DetectedModel]: ...


class GazeboCameraView:
    """The course plugin's model list for camera ``camera`` of ``station``, each model
    published as ``listing`` says (None: every model by its name, nested ones unnamed)."""

    def __init__(self, station: Station, camera: str, listing: Optional[ModelListing] = None):
        plant = station.plant
        self._listing = listing
        inspector = station.scene_graph.model_inspector()
        self._camera = station.cameras[camera]
        self._name = camera
        self._frustum = FrustumOverlap(self._camera.config)
        self._models = tuple(m for m in gazebo_models(plant, station.scenario) if m.name != camera)
        #: The last sample and its list: a sample is an immutable value, replaced at the next.
        self._last: Optional[tuple[CameraSample, LogicalCameraImage]] = None
        self._origins = [int(plant.GetBodyIndices(m.instances[0])[0]) for m in self._models]
        #: The bodies with geometry of the models without a fixed box, one row each (body
        #: index, box centre in B, half extents); model self._bodied[j] owns the rows from
        #: self._starts[j] on. self._fixed: the models with a fixed box.
        bodies: list[int] = []
        centres: list[np.ndarray] = []
        halves: list[np.ndarray] = []
        self._bodied: list[int] = []
        self._starts: list[int] = []
        self._fixed = [k for k, m in enumerate(self._models) if m.box_W is not None and m.own_links]
        self._fixed_boxes = [box for m in self._models if (box := m.box_W) is not None and m.own_links]
        #: The models every image lists (no links of their own: see GazeboModel.own_links).
        self._always = {k for k, m in enumerate(self._models) if not m.own_links}
        for k, model in enumerate(self._models):
            if model.box_W is not None or not model.own_links:
                continue
            start = len(bodies)
            for instance in model.instances:
                for body in plant.GetBodyIndices(instance):
                    geometries = body_geometries(plant, inspector, body)
                    box = bounding_box(inspector, geometries) if geometries else None
                    if box is not None:
                        bodies.append(int(body))
                        centres.append(box[0])
                        halves.append(box[1])
            if len(bodies) > start:
                self._bodied.append(k)
                self._starts.append(start)
        self._rows_body = bodies
        self._rows_centre = np.array(centres).reshape(-1, 3, 1)
        self._rows_half = np.array(halves).reshape(-1, 3, 1)

    @property
    def models(self) -> tuple[GazeboModel, ...]:
        """The models the camera may list (all but its own), in the world's order."""
        return self._models

    def _boxes_W(self, X_WB: list[RigidTransform]) -> tuple[list[int], np.ndarray, np.ndarray]:
        """The models with a box, in the world's order, and their world-aligned
        bounding boxes (lo, hi rows) with the bodies at X_WB."""
        ks = list(self._fixed)
        lo = [self._fixed_boxes[j][0] for j in range(len(ks))]
        hi = [self._fixed_boxes[j][1] for j in range(len(ks))]
        if self._bodied:
            T = np.array([X_WB[b].GetAsMatrix34() for b in self._rows_body])
            R = T[:, :, :3]
            c = (R @ self._rows_centre)[:, :, 0] + T[:, :, 3]
            h = (np.abs(R) @ self._rows_half)[:, :, 0]
            ks += self._bodied
            lo += list(np.minimum.reduceat(c - h, self._starts, axis=0))
            hi += list(np.maximum.reduceat(c + h, self._starts, axis=0))
        order = sorted(range(len(ks)), key=ks.__getitem__)
        return [ks[i] for i in order], np.array([lo[i] for i in order]), np.array([hi[i] for i in order])

    def image(self, root_context: Context) -> LogicalCameraImage:
        """The list for the camera's last sample in ``root_context`` (empty before its first)."""
        context = self._camera.GetMyContextFromRoot(root_context)
        sample = self._camera.sample(context)
        if self._last is not None and self._last[0] is sample:
            return self._last[1]
        image = self._list(sample, self._camera.image_output_port().Eval(context))
        self._last = (sample, image)
        return image

    def image_of(self, sample: CameraSample) -> LogicalCameraImage:
        """The list for ``sample``, one of the camera's samples (the last or an earlier one)."""
        if self._last is not None and self._last[0] is sample:
            return self._last[1]
        image = self._list(sample, self._camera.image_of(sample))
        self._last = (sample, image)
        return image

    def _list(self, sample: CameraSample, own: LogicalCameraImage) -> LogicalCameraImage:
        """The list for ``sample``, whose image (of the camera's own) is ``own``."""
        if sample.X_WB is None:
            return LogicalCameraImage(own.time, self._name, own.X_WC, ())
        X_WB = sample.X_WB.get_value()
        X_CW = own.X_WC.inverse()
        R_CW = X_CW.rotation().matrix()
        in_view = set(self._always)
        ks, lo, hi = self._boxes_W(X_WB)
        if ks:
            centres = (R_CW @ ((lo + hi) / 2).T).T + X_CW.translation()
            seen = self._frustum.overlaps(centres, np.repeat(R_CW[None], len(ks), axis=0), (hi - lo) / 2)
            in_view.update(k for k, s in zip(ks, seen.tolist()) if s)
        reported = {m.name: m.X_CM for m in own.models if m.name}
        listed: list[DetectedModel] = []
        for k in sorted(in_view):
            model = self._models[k]
            X_WM = model.X_WM if model.X_WM is not None else X_WB[self._origins[k]]
            X_CM_true = X_CW @ X_WM
            X_CM = reported.get(model.name, X_CM_true)
            if self._listing is None:
                listed.append(DetectedModel(model.name, model.type, X_CM))
                # Nested models carry no name: the plugin broadcasts no frame for them.
                listed += [DetectedModel("", model_type(name), X_CM @ X_MN) for name, X_MN in model.nested]
                continue
            top = self._listing.model(model.name, X_CM, X_CM_true)
            nested = [self._listing.nested(name, X_CM @ X_MN) for name, X_MN in model.nested]
            listed += [m for m in (top, *nested) if m is not None]
        return LogicalCameraImage(own.time, self._name, own.X_WC, tuple(listed))
