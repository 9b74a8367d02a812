"""The models a logical camera may report, and which of them overlap its frustum.

:class:`CameraCandidates` picks the candidate models of a plant (see
:class:`~omtp_drake.cell.logical_camera.LogicalCamera`, "Candidates") with the
bounding boxes of their bodies, and tests those boxes against the view frustum
for a sample. Frames as in :mod:`omtp_drake.cell.logical_camera` (``C`` the
camera, ``W`` the world, ``B`` a body, ``M`` a model's origin).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from pydrake.geometry import SceneGraphInspector
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex

from omtp_drake.cell.body_geometry import body_geometries, bounding_box
from omtp_drake.cell.camera_image import model_type
from omtp_drake.cell.frustum import FrustumOverlap
from omtp_drake.scenario.camera import LogicalCameraConfig

_log = logging.getLogger(__name__)

# The plant's model instances that are never candidates: world (0) and default (1).
_RESERVED_INSTANCES = (0, 1)


@dataclass(frozen=True)
class Candidate:
    """A model the camera may report, as it reports it."""

    name: str  # "" when anonymized
    type: str
    origin_body: int  # body index of M
    instance: int  # model instance index


class CameraCandidates:
    """The candidate models of a plant for the camera of ``config`` (``models``, in
    the plant's model-instance order) and the bounding boxes of their bodies, in the
    body frames: rows of ``_box_*``, candidate k owns rows
    [_box_starts[k], _box_starts[k + 1])."""

    def __init__(
        self,
        plant: MultibodyPlant,
        inspector: SceneGraphInspector,
        config: LogicalCameraConfig,
        exclude: set[int],
    ):
        self._frustum = FrustumOverlap(config)
        candidates: list[Candidate] = []
        box_body: list[int] = []
        box_centre: list[np.ndarray] = []
        box_half: list[np.ndarray] = []
        box_starts: list[int] = []
        for i in range(plant.num_model_instances()):
            instance = ModelInstanceIndex(i)
            name = plant.GetModelInstanceName(instance)
            if i in _RESERVED_INSTANCES or i in exclude or not _known(config, name):
                continue
            bodies = plant.GetBodyIndices(instance)
            boxes = []
            for body in bodies:
                geometries = body_geometries(plant, inspector, body)
                if geometries:
                    boxes.append((int(body), bounding_box(inspector, geometries)))
            if not boxes:
                continue
            bounded = [(body, box) for body, box in boxes if box is not None]
            if len(bounded) < len(boxes):
                _log.debug("%s: model %r has a HalfSpace; never reported", config.name, name)
                continue
            candidates.append(
                Candidate("" if config.anonymize else name, model_type(name), int(bodies[0]), i)
            )
            box_starts.append(len(box_body))
            for body, (centre, half) in bounded:
                box_body.append(body)
                box_centre.append(centre)
                box_half.append(half)
        self.models = tuple(candidates)
        self._box_body = tuple(box_body)
        self._box_centre = np.array(box_centre).reshape(-1, 3, 1)
        self._box_half = np.array(box_half).reshape(-1, 3)
        self._box_starts = np.array(box_starts, dtype=np.intp)
        _log.debug("%s: %d candidate models, %d boxes", config.name, len(candidates), len(box_body))

    def in_view(self, T_CW: np.ndarray, X_WB: Sequence[RigidTransform]) -> np.ndarray:
        """The indices of the candidates with a body box that overlaps the frustum.

        Args:
            T_CW: X_CW as a 3 x 4 matrix.
            X_WB: the world poses of every body, by body index.
        """
        # [R_CB | R_CW p_WB] of the bodies with boxes, then the box centres in C.
        T = T_CW[:, :3] @ np.array([X_WB[b].GetAsMatrix34() for b in self._box_body])
        R_CB = T[:, :, :3]
        p_CB = T[:, :, 3] + (R_CB @ self._box_centre)[:, :, 0] + T_CW[:, 3]
        seen = np.logical_or.reduceat(self._frustum.overlaps(p_CB, R_CB, self._box_half), self._box_starts)
        return np.flatnonzero(seen)


def _known(config: LogicalCameraConfig, name: str) -> bool:
    """The course plugin's rule (``known_model_types`` / ``known_model_names``,
    :class:`omtp_drake.gazebo.logical_camera.PluginListing`): with neither list every model;
    else one whose type is a known type or whose name is a known name (either list)."""
    if not config.known_types and not config.known_names:
        return True
    return model_type(name) in config.known_types or name in config.known_names
