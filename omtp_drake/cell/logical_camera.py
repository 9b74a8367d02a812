"""A Gazebo-like *logical camera*: names, types and poses of the models in view.

A logical camera does not render an image. Every update it reports which
models of the plant overlap its view frustum, and where each model's origin is
in the camera frame, like the ``LogicalCamera`` sensor of Gazebo that the
original course used (``osrf_gear/LogicalCameraImage``). Optionally
(``occlusion``) it reports only the models it can see, each with the visible
share of its image, from rays cast against the scene's visual geometry; an
image of the same view is the RGB-D view of :mod:`omtp_drake.cell.rgbd`.

Frames (monogram notation, ``X_AB`` is the pose of frame B in frame A):

* ``W``: the world frame.
* ``C``: the camera frame (the station's ``<name>_frame``, at
  :meth:`LogicalCameraConfig.X_PC` in its parent). Gazebo's convention: the
  camera looks along **+Cx**, +Cz is up and the image width runs along Cy. With
  rpy (0, 1.5708, 0) in the world the camera looks straight down.
* ``O``: the optical frame, the usual vision convention: +Oz forward (= +Cx),
  +Ox right (= -Cy), +Oy down (= -Cz); its pose in C is
  :func:`X_CameraOptical`.
* ``B``: a body frame; ``M``: a model's origin, the frame of the model
  instance's first body.

Typical use, once the plant (which has the camera frame) is finalized::

    camera = add_logical_camera(builder, plant, scene_graph, frame, config,
                                exclude=[camera_model_instance], seed=scenario_seed)
"""

# (no `from __future__ import annotations`: the config is a YAML schema)

import copy
import math
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import (
    SceneGraph,
    SceneGraphInspector,
)
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame, ModelInstanceIndex
from pydrake.systems.framework import Context, DiagramBuilder, InputPort, LeafSystem, OutputPort, State

from omtp_drake.cell.camera_candidates import CameraCandidates
from omtp_drake.cell.camera_image import DetectedModel, LogicalCameraImage, model_type
from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.occlusion import AllVisible, RayCastOcclusion
from omtp_drake.errors import ConfigError
from omtp_drake.scenario.camera import LogicalCameraConfig

#: The camera's public names; the image types live in :mod:`omtp_drake.cell.camera_image`
#: and are named here too, where users of the camera import them.
__all__ = [
    "CameraSample",
    "DetectedModel",
    "LogicalCamera",
    "LogicalCameraImage",
    "X_CameraOptical",
    "add_logical_camera",
    "add_pose_noise",
    "model_type",
]


def X_CameraOptical() -> RigidTransform:
    """The optical frame O in the camera frame C: Oz = Cx, Ox = -Cy, Oy = -Cz."""
    R_CO = RotationMatrix(np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]))
    return RigidTransform(R_CO, np.zeros(3))


def add_pose_noise(X_CM: RigidTransform, dp: Any, R_pert: RotationMatrix) -> RigidTransform:
    """``X_CM`` with a noise draw on it, as the course's ``ROSLogicalCameraPlugin::AddNoise``:
    the offsets ``dp`` added to the position, and the orientation perturbation ``R_pert``
    (the draw's roll, pitch, yaw) composed on the right, ``Rot *= pert``: R_CM @ R_pert,
    a perturbation about the model's own axes. The one rule of the camera's pose noise (the
    message's models and an AGV's kit tray alike)."""
    return RigidTransform(X_CM.rotation() @ R_pert, X_CM.translation() + np.asarray(dp))


@dataclass(frozen=True)
class CameraSample:
    """A logical camera's state: when it last sampled and where every body was then
    (``X_WB``: the plant's body poses as the abstract value of its port, a list of
    ``RigidTransform`` by body index; None before the first sample).

    The poses stay a C++ copy until an image is computed: turning them into Python
    objects is left to the image, as most samples are never looked at."""

    time: float = math.nan
    X_WB: Optional[AbstractValue] = None

    def __deepcopy__(self, memo: dict[int, Any]) -> "CameraSample":
        # Drake clones abstract state values on every update; a sample is immutable.
        return self


class LogicalCamera(LeafSystem):
    """Reports the models of a MultibodyPlant that overlap a view frustum.

    .. pydrake_system::

        name: LogicalCamera
        input_ports:
        - body_poses
        output_ports:
        - image

    - ``body_poses`` (abstract ``list[RigidTransform]``,
      :meth:`body_poses_input_port`): the plant's
      ``get_body_poses_output_port()``, X_WB of every body by body index.
    - ``image`` (abstract :class:`LogicalCameraImage`,
      :meth:`image_output_port`): the last sample. The
      camera samples at ``config.update_rate_hz`` from t = 0 (and at
      initialization), and holds the sample in between: at t = 0.25 with
      10 Hz the image's time is 0.2. Before the context is initialized the
      image is empty with time NaN. A forced event (``ExecuteForcedEvents``)
      captures an image at the context's time on demand.

    State: the last sample, i.e. its time and the body poses then
    (:class:`CameraSample`; a sample only copies the poses). The image is
    computed from the sample when the ``image`` port is read, and cached until
    the next sample: a camera nobody reads costs no frustum, occlusion or noise
    work, and one read several times per sample computes it once.

    Frames: the camera frame C is the plant frame ``frame``; it looks along +Cx,
    +Cz up, the width along Cy (Gazebo's logical camera; see the module
    docstring and :func:`X_CameraOptical` for the optical frame).

    Frustum: the truncated pyramid between the planes x = near and x = far of
    C, with half-width x tan(fov / 2) along Cy and half-height
    x tan(fov / 2) / aspect_ratio along Cz.

    Candidates: every model instance of the plant except world, default and
    ``exclude`` (the camera's own model), that has geometry (proximity or
    illustration) and is known (its type in ``known_types`` or its name in ``known_names``,
    as the course plugin's lists; every model when both are empty). A model with a
    HalfSpace (unbounded, e.g. a floor) is never reported. The bounding box of
    a body is the axis-aligned box, in the body frame, of its geometries'
    oriented bounding boxes (meshes: of their vertices).

    A model is seen when the oriented bounding box of any of its bodies
    overlaps the frustum (exact separating-axis test; partial overlap counts).
    It is reported with the pose X_CM of its origin M, the frame of its first
    body; with ``anonymize`` its name is reported as "".

    Occlusion (``config.occlusion``): a model in view is reported only when
    its ``visible_fraction`` is at least ``config.min_visible_fraction``. The
    fraction is the share of the model's image (its visual geometry as seen
    from the camera's origin, inside the image and between ``near`` and
    ``far``) whose first surface is the model's, not another model's (any
    model's, the floor's and those of unreported models included); 0 when
    none of its geometry shows. Visual geometry: a body's perception
    geometries (else illustration, else proximity ones), each as a convex
    polytope: exact for boxes, the 26-DOP of a mesh's convex hull or of a
    round shape (which may hide up to about 10 % more than the mesh does).
    It is measured on a grid of ``OCCLUSION_GRID`` x ``OCCLUSION_GRID`` rays
    over the model's image rectangle
    (:class:`~omtp_drake.cell.occlusion.RayCastOcclusion`), so a far,
    small model is resolved as finely as a near one. Without occlusion every
    model in view has ``visible_fraction`` 1.0 and nothing more is computed.

    Noise (when the sigmas are positive), in C: p_CM += N(0, sigma_p) per axis,
    R_CM <- R(roll, pitch, yaw) R_CM with roll, pitch, yaw ~ N(0, sigma_o).
    The draws are a function of (seed, camera name, sample index = round(t *
    rate), model): the same seed gives the same sequence, without hidden state.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        scene_graph_inspector: SceneGraphInspector,
        frame: Frame,
        config: LogicalCameraConfig,
        *,
        exclude: Sequence[ModelInstanceIndex] = (),
        seed: int = 0,
    ):
        super().__init__()
        if seed < 0:
            raise ConfigError(f"logical camera {config.name!r}: seed={seed!r} is invalid; valid: seed >= 0")
        if not plant.is_finalized():
            raise ConfigError(f"logical camera {config.name!r}: the plant must be finalized first")
        self.set_name(config.name)
        self._config = copy.deepcopy(config)
        self._name = config.name
        self._rate = config.update_rate_hz
        self._seed_key = (config.seed if config.seed is not None else seed, zlib.crc32(config.name.encode()))
        self._camera_body = int(frame.body().index())
        self._X_BC = frame.GetFixedPoseInBodyFrame()
        candidates = CameraCandidates(plant, scene_graph_inspector, config, {int(i) for i in exclude})
        self._in_view = candidates.in_view
        self._candidates = candidates.models
        # The one variant point: how much of each model in view is visible.
        self._visibility: AllVisible | RayCastOcclusion = (
            RayCastOcclusion(
                plant, scene_graph_inspector, config, {c.instance: k for k, c in enumerate(self._candidates)}
            )
            if config.occlusion
            else AllVisible()
        )

        self._body_poses_port = self.DeclareAbstractInputPort(
            "body_poses", plant.get_body_poses_output_port().Allocate()
        )
        period = 1.0 / config.update_rate_hz
        self._sample = self.DeclareAbstractState(AbstractValue.Make(CameraSample()))
        # Fault injection: no new images before this time (see black_out()).
        self._blackout = self.DeclareDiscreteState(np.array([-math.inf]))
        self.DeclareInitializationUnrestrictedUpdateEvent(self._update)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, 0.0, self._update)
        self.DeclareForcedUnrestrictedUpdateEvent(self._update)
        self._no_image = no_image = LogicalCameraImage(
            time=math.nan, camera_name=config.name, X_WC=RigidTransform(), models=()
        )
        self._image_port = self.DeclareAbstractOutputPort(  # C++ holds the callbacks (see cell.lifetime)
            "image",
            lambda: AbstractValue.Make(no_image),
            weak_method(self._calc_image),
            prerequisites_of_calc={self.abstract_state_ticket(self._sample)},
        )

    def body_poses_input_port(self) -> InputPort:
        """The ``body_poses`` input: the plant's body poses X_WB, by body index."""
        return self._body_poses_port

    def image_output_port(self) -> OutputPort:
        """The ``image`` output: the last :class:`LogicalCameraImage`."""
        return self._image_port

    @property
    def config(self) -> LogicalCameraConfig:
        """A copy of the camera's configuration."""
        return copy.deepcopy(self._config)

    def _update(self, context: Context, state: State) -> None:
        time = context.get_time()
        if time < context.get_discrete_state(self._blackout)[0]:
            return  # blacked out: the last sample is held (its image goes stale)
        sample = CameraSample(time, self._body_poses_port.EvalAbstract(context).Clone())
        state.get_mutable_abstract_state(self._sample).set_value(sample)

    def _calc_image(self, context: Context, output: AbstractValue) -> None:
        output.set_value(self.image_of(context.get_abstract_state(self._sample).get_value()))

    def image_of(self, sample: CameraSample) -> LogicalCameraImage:
        """The image of ``sample``: what the ``image`` output gives while ``sample`` is the
        camera's last (an image is a function of its sample, the noise seeded by its time)."""
        if sample.X_WB is None:
            return self._no_image
        return self._capture(sample.time, sample.X_WB.get_value())

    def sample(self, context: Context) -> CameraSample:
        """The camera's last sample: its time and the body poses then."""
        return context.get_abstract_state(self._sample).get_value()

    def black_out(self, context: Context, until: float) -> None:
        """Fault injection: the camera publishes no new image before ``until``
        (its output keeps the last image, whose time shows it is stale)."""
        context.SetDiscreteState(self._blackout, np.array([float(until)]))

    def _capture(self, time: float, X_WB: Sequence[RigidTransform]) -> "LogicalCameraImage":
        """The image at ``time``, when the bodies were at ``X_WB`` (by body index)."""
        X_WC = X_WB[self._camera_body] @ self._X_BC
        occlusion = self._visibility.occlusion
        if not self._candidates:
            return LogicalCameraImage(time, self._name, X_WC, (), occlusion)
        X_CW = X_WC.inverse()
        T_CW = X_CW.GetAsMatrix34()
        indices = self._in_view(T_CW, X_WB)
        fractions = self._visibility.fractions(T_CW, X_WB, indices)
        if occlusion:
            visible = fractions >= self._config.min_visible_fraction
            indices, fractions = indices[visible], fractions[visible]
        if not len(indices):
            return LogicalCameraImage(time, self._name, X_WC, (), occlusion)
        noise = self._noise(time)
        models = []
        for k, fraction in zip(indices.tolist(), fractions.tolist()):
            candidate = self._candidates[k]
            X_CM = X_CW @ X_WB[candidate.origin_body]
            if noise is not None:
                X_CM = add_pose_noise(X_CM, noise[k, :3], RollPitchYaw(noise[k, 3:]).ToRotationMatrix())
            models.append(DetectedModel(candidate.name, candidate.type, X_CM, fraction))
        return LogicalCameraImage(time, self._name, X_WC, tuple(models), occlusion)

    def _noise(self, time: float) -> Optional[np.ndarray]:
        """(candidates, 6) rows [dx, dy, dz, roll, pitch, yaw] of the sample at ``time``,
        or None without noise."""
        sigma_p = self._config.position_noise_sigma
        sigma_o = self._config.orientation_noise_sigma
        if sigma_p == 0 and sigma_o == 0:
            return None
        rng = np.random.default_rng((*self._seed_key, round(time * self._rate)))
        return rng.standard_normal((len(self._candidates), 6)) * np.repeat([sigma_p, sigma_o], 3)


def add_logical_camera(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    frame: Frame,
    config: LogicalCameraConfig,
    *,
    exclude: Sequence[ModelInstanceIndex] = (),
    seed: int = 0,
) -> LogicalCamera:
    """Adds a LogicalCamera (named ``config.name``) to ``builder`` and connects
    the plant's body poses to it. ``frame``, ``exclude`` and ``seed`` are as in
    :class:`LogicalCamera`; the plant must be finalized.

    Raises:
        ConfigError: invalid ``config`` or ``seed`` (nothing is added then).
    """
    config.validate()
    camera = LogicalCamera(plant, scene_graph.model_inspector(), frame, config, exclude=exclude, seed=seed)
    builder.AddSystem(camera)
    builder.Connect(plant.get_body_poses_output_port(), camera.body_poses_input_port())
    return camera
