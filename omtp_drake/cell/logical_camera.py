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
import logging
import math
import re
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional, TypeVar

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.geometry import (
    Box,
    Capsule,
    Convex,
    Cylinder,
    Ellipsoid,
    GeometryId,
    HalfSpace,
    Mesh,
    Obb,
    Role,
    SceneGraph,
    SceneGraphInspector,
    Sphere,
)
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, Frame, ModelInstanceIndex
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, State

from omtp_drake.errors import ConfigError, FrameError
from omtp_drake.scenario.camera import LogicalCameraConfig

if TYPE_CHECKING:
    from omtp_drake.cell.poses import PoseStamped

_log = logging.getLogger(__name__)

_TRAILING_INDEX = re.compile(r"_\d+$")

# The plant's model instances that are never candidates: world (0) and default (1).
_RESERVED_INSTANCES = (0, 1)


# ----------------------------------------------------------------------------
# Configuration


def X_CameraOptical() -> RigidTransform:
    """The optical frame O in the camera frame C: Oz = Cx, Ox = -Cy, Oy = -Cz."""
    R_CO = RotationMatrix(np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]))
    return RigidTransform(R_CO, np.zeros(3))


# ----------------------------------------------------------------------------
# Output values


def model_type(name: str) -> str:
    """A model's name without a trailing ``_<digits>`` (``object_3`` -> ``object``)."""
    return _TRAILING_INDEX.sub("", name)


def _pose_dict(X: RigidTransform) -> dict[str, list[float]]:
    """Translation and quaternion [x, y, z, w] (w >= 0, Drake's canonical form)."""
    q = X.rotation().ToQuaternion()
    # `+ 0.0` turns -0.0 into 0.0.
    return {
        "translation": [float(v) + 0.0 for v in X.translation()],
        "rotation_xyzw": [float(v) + 0.0 for v in (q.x(), q.y(), q.z(), q.w())],
    }


def _pose_lines(X: RigidTransform, indent: str) -> list[str]:
    pose = _pose_dict(X)
    lines = [f"{indent}pose:", f"{indent}  position:"]
    lines += [f"{indent}    {k}: {v!r}" for k, v in zip("xyz", pose["translation"])]
    lines.append(f"{indent}  orientation:")
    lines += [f"{indent}    {k}: {v!r}" for k, v in zip("xyzw", pose["rotation_xyzw"])]
    return lines


@dataclass(frozen=True)
class DetectedModel:
    """One model in view.

    Attributes:
        name: the model instance's name (``""`` when the camera anonymizes).
        type: the name without a trailing ``_<digits>`` (see :func:`model_type`).
        X_CM: pose of the model's origin M (its first body's frame) in the camera frame C.
        visible_fraction: the share of the model's image that is not hidden by
            other geometry (see :class:`LogicalCamera`); 1.0 when the camera
            does not test occlusion.
    """

    name: str
    type: str
    X_CM: RigidTransform
    visible_fraction: float = 1.0


@dataclass(frozen=True)
class LogicalCameraImage:
    """One sample of a logical camera.

    Attributes:
        time: the sample time [s].
        camera_name: the camera's name.
        X_WC: the camera frame's pose in the world at ``time``.
        models: the models in view, in the plant's model-instance order.
        occlusion: whether the camera tested occlusion (each model's
            ``visible_fraction`` was measured; it is printed then).

    Images are values: the poses they hold must not be mutated (copies of an
    image share them).
    """

    time: float
    camera_name: str
    X_WC: RigidTransform
    models: tuple[DetectedModel, ...]
    occlusion: bool = False

    def __deepcopy__(self, memo: dict[int, Any]) -> "LogicalCameraImage":
        # Drake clones abstract state values on every update; an image is immutable.
        return self

    @property
    def frame(self) -> str:
        """The camera frame's name in tf (``<camera>_frame``)."""
        return f"{self.camera_name}_frame"

    def pose_of(self, name: str) -> "PoseStamped":
        """The pose of model ``name`` as reported, in the camera frame, stamped with
        the image's time (for ``TfBuffer.transform_pose``)."""
        from omtp_drake.cell.poses import PoseStamped

        for m in self.models:
            if m.name == name:
                return PoseStamped(self.frame, self.time, m.X_CM)
        raise FrameError(
            f"{self.camera_name} does not see {name!r} in its image at t = {self.time:.6g} s; "
            f"it sees: {', '.join(m.name or '(anonymous)' for m in self.models) or 'nothing'}"
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain data (for JSON/YAML); quaternions are [x, y, z, w] with w >= 0."""
        return {
            "time": self.time,
            "camera_name": self.camera_name,
            "camera_pose": _pose_dict(self.X_WC),
            "models": [
                {
                    "name": m.name,
                    "type": m.type,
                    "pose": _pose_dict(m.X_CM),
                    "visible_fraction": float(m.visible_fraction),
                }
                for m in self.models
            ],
        }

    def __str__(self) -> str:
        """Renders like ``rostopic echo`` of the original ``LogicalCameraImage`` message
        (with occlusion, each model also shows its ``visible_fraction``)."""
        lines = [f"time: {round(self.time, 9)!r}", f'camera_name: "{self.camera_name}"']
        lines += _pose_lines(self.X_WC, "")
        if not self.models:
            lines.append("models: []")
        else:
            lines.append("models:")
            for m in self.models:
                lines += ["  -", f'    name: "{m.name}"', f'    type: "{m.type}"']
                lines += _pose_lines(m.X_CM, "    ")
                if self.occlusion:
                    lines.append(f"    visible_fraction: {round(m.visible_fraction, 4)!r}")
        lines.append("---")
        return "\n".join(lines)


# ----------------------------------------------------------------------------
# The frustum overlap test (separating axes)


def _skew(v: np.ndarray) -> np.ndarray:
    """[v]x, so that ``_skew(v) @ a == np.cross(v, a)``."""
    x, y, z = v
    return np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]], float)


class _FrustumOverlap:
    """Exact overlap test of many oriented boxes against the view frustum.

    The frustum, in C, is {near <= x <= far, |y| <= x ty, |z| <= x tz} with
    ty = tan(fov / 2), tz = ty / aspect: the intersection of the 6 half-spaces
    n_k . p <= b_k. Both shapes are convex polyhedra, so they are disjoint iff
    their projections on one of these axes L are (the separating-axis
    theorem): the frustum face normals n_k, the 3 box face normals, and the 18
    cross products of a frustum edge direction (6) with a box edge direction
    (3).

    Projections: a box with centre c, axes a_i and half-extents h_i projects
    on L to c . L +- sum_i |a_i . L| h_i. The frustum's vertices are
    d (1, +-ty, +-tz) for d in {near, far}, so it projects to
    [min(near g-, far g-), max(near g+, far g+)] with
    g+- = Lx +- (ty |Ly| + tz |Lz|).

    A cross product of parallel edges is the zero vector: both projections are
    the point 0 and it never separates. A tiny one from rounding is still a
    genuine direction, so no axis needs special treatment.
    """

    def __init__(self, config: LogicalCameraConfig):
        ty = math.tan(config.horizontal_fov / 2)
        tz = ty / config.aspect_ratio
        self._near = config.near
        self._far = config.far
        self._lateral = np.array([0.0, ty, tz])
        # Half-spaces n_k . p <= b_k: near, far, +y, -y, +z, -z sides.
        self._face_normals = np.array(
            [[-1, 0, 0], [1, 0, 0], [-ty, 1, 0], [-ty, -1, 0], [-tz, 0, 1], [-tz, 0, -1]], float
        )
        self._face_offsets = np.array([-config.near, config.far, 0, 0, 0, 0], float)
        edges = np.array(
            [[0, 1, 0], [0, 0, 1], [1, ty, tz], [1, ty, -tz], [1, -ty, tz], [1, -ty, -tz]], float
        )
        # A row vector a times this (3, 21) matrix = the rows a, e_0 x a, ..., e_5 x a.
        self._axis_rows = np.concatenate([np.eye(3)] + [_skew(e).T for e in edges], axis=1)

    def overlaps(self, p_CB: np.ndarray, R_CB: np.ndarray, half: np.ndarray) -> np.ndarray:
        """Which of n boxes overlap the frustum (touching counts).

        The face normals first: a box is out if one separates it, in if its
        centre is in every half-space; then in if its vertex deepest behind the
        most violated face is in every half-space; the other axes only for the rest.

        Args:
            p_CB: (n, 3) box centres in C.
            R_CB: (n, 3, 3) box orientations in C (columns: the box axes).
            half: (n, 3) half-extents along the box axes.
        Returns:
            (n,) bool.
        """
        distance = self._face_distances(p_CB)
        radius = (np.abs(self._face_normals @ R_CB) @ half[:, :, None])[:, :, 0]
        result = (distance <= 0).all(axis=1)
        undecided = np.flatnonzero(~(result | (distance > radius).any(axis=1)))
        if len(undecided):
            # A box vertex inside the frustum proves an overlap: try, for each box,
            # its vertex deepest behind the face its centre is farthest outside of
            # (a box straddling one face is settled here, without the 21 axes).
            normal = self._face_normals[distance[undecided].argmax(axis=1)]  # (m, 3)
            R = R_CB[undecided]
            toward = np.sign((normal[:, None, :] @ R)[:, 0, :])  # +-1 per box axis
            vertex = p_CB[undecided] - (R @ (toward * half[undecided])[:, :, None])[:, :, 0]
            inside = (self._face_distances(vertex) <= 0).all(axis=1)
            result[undecided[inside]] = True
            rest = undecided[~inside]
            if len(rest):
                result[rest] = self._not_separated_by_edges_or_box(p_CB[rest], R_CB[rest], half[rest])
        return result

    def _face_distances(self, p_C: np.ndarray) -> np.ndarray:
        """n_k . p - b_k for points p (n, 3) in C and the six faces (near, far,
        +y, -y, +z, -z): (n, 6), > 0 where p is outside that face."""
        return p_C @ self._face_normals.T - self._face_offsets

    def _not_separated_by_edges_or_box(
        self, p_CB: np.ndarray, R_CB: np.ndarray, half: np.ndarray
    ) -> np.ndarray:
        """No box normal nor edge cross product separates (arguments as :meth:`overlaps`)."""
        n = len(p_CB)
        axes = (R_CB.transpose(0, 2, 1).reshape(-1, 3) @ self._axis_rows).reshape(n, 21, 3)
        lateral = np.abs(axes) @ self._lateral  # (n, 21)
        g_plus = axes[:, :, 0] + lateral
        g_minus = axes[:, :, 0] - lateral
        frustum_max = np.maximum(self._near * g_plus, self._far * g_plus)
        frustum_min = np.minimum(self._near * g_minus, self._far * g_minus)
        centre = (axes @ p_CB[:, :, None])[:, :, 0]
        radius = (np.abs(axes @ R_CB) @ half[:, :, None])[:, :, 0]
        separated = (centre - radius > frustum_max) | (centre + radius < frustum_min)
        return ~separated.any(axis=1)


# ----------------------------------------------------------------------------
# Bounding boxes


def _geometries(
    plant: MultibodyPlant, inspector: SceneGraphInspector, body_index: BodyIndex
) -> list[GeometryId]:
    """The proximity and illustration geometries of a body."""
    frame_id = plant.GetBodyFrameIdIfExists(body_index)
    if frame_id is None:
        return []
    geometries = set(inspector.GetGeometries(frame_id, Role.kProximity))
    geometries |= set(inspector.GetGeometries(frame_id, Role.kIllustration))
    return sorted(geometries, key=lambda g: g.get_value())


T = TypeVar("T")

#: What is computed from a mesh file, by (what, file, scale): a mesh's bounding box
#: and convex hull take milliseconds each (a UR arm's hulls about 0.25 s in all), and
#: every camera of every station built in a process needs those of every arm. Pure
#: functions of the file, so a memo, not state.
_MESH_MEMO: dict[tuple[str, str, tuple[float, ...]], Any] = {}


def _per_mesh_file(
    what: str, inspector: SceneGraphInspector, geometry_id: GeometryId, compute: Callable[[], T]
) -> T:
    """``compute()``, once per mesh file and scale for a Mesh or Convex from a file."""
    shape = inspector.GetShape(geometry_id)
    if not (isinstance(shape, (Mesh, Convex)) and shape.source().is_path()):
        return compute()
    key = (what, f"{type(shape).__name__}:{shape.source().path()}", tuple(shape.scale3()))
    if key not in _MESH_MEMO:
        _MESH_MEMO[key] = compute()
    return _MESH_MEMO[key]


def _obb(inspector: SceneGraphInspector, geometry_id: GeometryId) -> Optional[Obb]:
    """The geometry's oriented bounding box in its frame (None: unbounded), computed
    once per mesh file and scale."""
    return _per_mesh_file("obb", inspector, geometry_id, lambda: inspector.GetObbInGeometryFrame(geometry_id))


_BOX_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)


def _bounding_box(
    inspector: SceneGraphInspector, geometries: Sequence[GeometryId]
) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """The axis-aligned box (centre, half-extents), in the frame F they are
    registered to, of the oriented bounding boxes of ``geometries`` (analytic
    for primitives, from the vertices for meshes); None if one of them is
    unbounded (a HalfSpace)."""
    corners = []
    for geometry_id in geometries:
        obb = _obb(inspector, geometry_id)
        if obb is None:
            return None
        X_FO = inspector.GetPoseInFrame(geometry_id) @ obb.pose()
        corners.append(
            X_FO.rotation().matrix() @ (_BOX_CORNERS * obb.half_width()).T + X_FO.translation()[:, None]
        )
    points = np.concatenate(corners, axis=1)
    low, high = points.min(axis=1), points.max(axis=1)
    return (low + high) / 2, (high - low) / 2


# ----------------------------------------------------------------------------
# Occlusion: rays cast against the visual geometry


#: Rays per side of the grid cast over each model's image rectangle: 16 x 16 =
#: 256 rays, so a model's visible fraction is resolved to about 1 / 16 along an
#: occluding edge whatever its size in the image (bench/bench_occlusion.py).
OCCLUSION_GRID = 16

#: The 13 slab directions of a 26-DOP: the 3 axes, the 6 face diagonals and the
#: 4 body diagonals (unit vectors).
_DOP_DIRECTIONS = np.array(
    [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1], [0, 1, 1],
     [0, 1, -1], [1, 1, 1], [1, 1, -1], [1, -1, 1], [1, -1, -1]],
    float,
)  # fmt: skip
_DOP_DIRECTIONS /= np.linalg.norm(_DOP_DIRECTIONS, axis=1, keepdims=True)


def _slabs_in_geometry_frame(
    inspector: SceneGraphInspector, geometry_id: GeometryId
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The convex polytope standing for a geometry, in its frame G, as slabs
    {p_G : -d_minus_k <= n_k . p_G <= d_plus_k}: (n (k, 3) unit, d_plus (k,),
    d_minus (k,)). Exact for a Box (3 slabs) and a HalfSpace (z <= 0: one slab
    with d_minus = inf); the 26-DOP (the tightest polytope whose faces have the
    normals +-:data:`_DOP_DIRECTIONS`) of a Sphere, Cylinder, Capsule or
    Ellipsoid, and of the convex hull of a Mesh or Convex; the oriented
    bounding box of any other shape."""
    shape = inspector.GetShape(geometry_id)
    n = _DOP_DIRECTIONS
    if isinstance(shape, Box):
        half = np.array([shape.width(), shape.depth(), shape.height()]) / 2
        return np.eye(3), half, half
    if isinstance(shape, HalfSpace):
        return np.array([[0.0, 0.0, 1.0]]), np.zeros(1), np.full(1, np.inf)
    if isinstance(shape, (Mesh, Convex)):

        def hull_slabs() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            hull = inspector.GetConvexHull(geometry_id)
            along = np.array([hull.vertex(i) for i in range(hull.num_vertices())]) @ n.T
            return n, along.max(axis=0), -along.min(axis=0)

        return _per_mesh_file("dop", inspector, geometry_id, hull_slabs)
    # Centrally symmetric shapes: d_plus = d_minus = the support function h(n).
    if isinstance(shape, Sphere):
        h = np.full(len(n), shape.radius())
    elif isinstance(shape, Cylinder):
        h = shape.radius() * np.hypot(n[:, 0], n[:, 1]) + shape.length() / 2 * np.abs(n[:, 2])
    elif isinstance(shape, Capsule):
        h = shape.radius() + shape.length() / 2 * np.abs(n[:, 2])
    elif isinstance(shape, Ellipsoid):
        h = np.linalg.norm(n * [shape.a(), shape.b(), shape.c()], axis=1)
    else:
        obb = _obb(inspector, geometry_id)
        if obb is None:  # (only a HalfSpace is unbounded, handled above)
            raise ConfigError(f"geometry {inspector.GetName(geometry_id)!r} has no bounding box")
        axes = obb.pose().rotation().matrix().T  # rows: the box's axes in G
        centre = axes @ obb.pose().translation()
        return axes, obb.half_width() + centre, obb.half_width() - centre
    return n, h, h


def _visual_geometries(
    plant: MultibodyPlant, inspector: SceneGraphInspector, body_index: BodyIndex
) -> list[GeometryId]:
    """What a camera sees of a body: its perception geometries, else its
    illustration ones, else its proximity ones (a body modelled for one role only
    is still seen)."""
    frame_id = plant.GetBodyFrameIdIfExists(body_index)
    if frame_id is None:
        return []
    for role in (Role.kPerception, Role.kIllustration, Role.kProximity):
        geometries = inspector.GetGeometries(frame_id, role)
        if geometries:
            return sorted(geometries, key=lambda g: g.get_value())
    return []


class _AllVisible:
    """Visibility without occlusion: every model in view is fully visible (no work)."""

    occlusion = False

    def fractions(self, T_CW: np.ndarray, X_WB: Sequence[RigidTransform], seen: np.ndarray) -> np.ndarray:
        return np.ones(len(seen))


class _RayCastOcclusion:
    """The visible fraction of models, from rays cast against the scene's visual
    geometry (see :class:`LogicalCamera`, "Occlusion").

    Every visual geometry of the plant (:func:`_visual_geometries`) is a convex
    polytope fixed to its body (:func:`_slabs_in_geometry_frame`), with the
    oriented bounding box that culls it. For a sample: the geometries whose box
    overlaps the frustum; for each model in view, a grid of
    ``OCCLUSION_GRID`` x ``OCCLUSION_GRID`` rays from the camera's origin
    through its geometries' image rectangle (clipped to the image), tested
    against its own polytopes and those of the other geometries whose
    rectangle overlaps it and that come nearer than its farthest point. A ray
    sees the first polytope surface between ``near`` and ``far`` (a solid cut by
    the near plane shows its inside, as a renderer without back-face culling
    does). The model's fraction is (rays whose first surface is the model's) /
    (rays that meet the model at all); 0 when none do.

    A ray through the image point (y, z) (normalised: y = Cy / Cx, z = Cz / Cx)
    is p(t) = t (1, y, z): its parameter is the depth Cx, so the clipping
    planes bound t, and a slab -d_minus <= n . p <= d_plus holds t between
    d_plus / a and -d_minus / a, a = n . (1, y, z) (the slab method: a polytope
    is met on [max of the slabs' lower ends, min of their upper ends]).
    """

    occlusion = True

    def __init__(
        self,
        plant: MultibodyPlant,
        inspector: SceneGraphInspector,
        config: LogicalCameraConfig,
        owners: dict[int, int],
    ):
        """``owners``: model instance index -> the index of the candidate it is."""
        self._near, self._far = config.near, config.far
        self._frustum = _FrustumOverlap(config)
        ty = math.tan(config.horizontal_fov / 2)
        self._image_low = np.array([-ty, -ty / config.aspect_ratio])
        self._image_high = -self._image_low
        bodies: list[int] = []
        owner, body_row, R_BO, p_BO, half = [], [], [], [], []
        normals, d_plus, d_minus, counts = [], [], [], []
        for index in range(plant.num_bodies()):
            body = plant.get_body(BodyIndex(index))
            geometries = _visual_geometries(plant, inspector, body.index())
            if not geometries:
                continue
            bodies.append(index)
            for geometry_id in geometries:
                X_BG = inspector.GetPoseInFrame(geometry_id)
                n_G, plus, minus = _slabs_in_geometry_frame(inspector, geometry_id)
                n_B = n_G @ X_BG.rotation().matrix().T
                shift = n_B @ X_BG.translation()  # n_B . p_B = n_G . p_G + n_B . p_BG
                normals.append(n_B)
                d_plus.append(plus + shift)
                d_minus.append(minus - shift)
                counts.append(len(n_B))
                obb = _obb(inspector, geometry_id)  # None: unbounded
                X_BO = X_BG @ obb.pose() if obb is not None else RigidTransform()
                R_BO.append(X_BO.rotation().matrix())
                p_BO.append(X_BO.translation())
                half.append(obb.half_width() if obb is not None else np.full(3, np.inf))
                owner.append(owners.get(int(body.model_instance()), -1))
                body_row.append(len(bodies) - 1)
        self._bodies = tuple(bodies)
        self._owner = np.array(owner, dtype=np.intp)
        self._body_row = np.array(body_row, dtype=np.intp)
        self._R_BO = np.array(R_BO).reshape(-1, 3, 3)
        self._p_BO = np.array(p_BO).reshape(-1, 3, 1)
        self._half = np.array(half).reshape(-1, 3)
        bounded = np.isfinite(self._half).all(axis=1)
        self._bounded, self._unbounded = np.flatnonzero(bounded), np.flatnonzero(~bounded)
        self._normals = np.concatenate(normals) if normals else np.zeros((0, 3))
        self._d_plus = np.concatenate(d_plus) if d_plus else np.zeros(0)
        self._d_minus = np.concatenate(d_minus) if d_minus else np.zeros(0)
        self._slab_counts = np.array(counts, dtype=np.intp)
        self._slab_start = np.cumsum(self._slab_counts) - self._slab_counts  # each geometry's first slab
        self._slab_geometry = np.repeat(np.arange(len(counts)), counts)
        # A cell-centred grid g on [0, 1]^2 (scaled onto each model's rectangle), as
        # columns 1, g_y, g_z.
        u = (np.arange(OCCLUSION_GRID) + 0.5) / OCCLUSION_GRID
        grid = np.stack(np.meshgrid(u, u, indexing="ij"), axis=-1).reshape(-1, 2)
        self._grid_columns = np.concatenate([np.ones((len(grid), 1)), grid], axis=1)

    def fractions(self, T_CW: np.ndarray, X_WB: Sequence[RigidTransform], seen: np.ndarray) -> np.ndarray:
        """The visible fraction of each candidate in ``seen`` (indices).

        Args:
            T_CW: X_CW as a 3 x 4 matrix.
            X_WB: the world poses of every body, by body index.
            seen: indices of the candidates that overlap the frustum.
        """
        result = np.zeros(len(seen))
        if not len(seen) or not len(self._owner):
            return result
        T = T_CW[:, :3] @ np.array([X_WB[b].GetAsMatrix34() for b in self._bodies])
        R_CB = T[:, :, :3]
        p_CB = T[:, :, 3] + T_CW[:, 3]
        view, R_CO, p_CO = self._geometries_in_view(R_CB, p_CB)
        own = self._owner[view] == seen[:, None]  # (models, geometries in view)
        if not own.any():
            return result
        low, high, depth_min, depth_max = self._image_rectangles(view, R_CO, p_CO)
        pairs = self._pairs_to_test(own, low, high, depth_min, depth_max)
        if pairs is None:
            return result
        model, geometry, mine, lo, hi = pairs
        depth = self._ray_depths(view, model, geometry, lo, hi, R_CB, p_CB)
        first = np.flatnonzero(np.r_[True, model[1:] != model[:-1]])  # each model's first pair
        own_depth = np.minimum.reduceat(np.where(mine, depth, np.inf), first, axis=1)
        other_depth = np.minimum.reduceat(np.where(mine, np.inf, depth), first, axis=1)
        met = np.isfinite(own_depth)
        met_first = (met & (own_depth <= other_depth)).sum(axis=0)
        result[model[first]] = met_first / np.maximum(met.sum(axis=0), 1)
        return result

    def _geometries_in_view(
        self, R_CB: np.ndarray, p_CB: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The geometries in view: unbounded, or their box overlaps the frustum.

        Returns their geometry indices (the bounded ones first) and the poses in C
        (R_CO, p_CO) of the bounded ones' boxes, in the same order.
        """
        bounded = self._bounded
        rows = self._body_row[bounded]
        R_CO = R_CB[rows] @ self._R_BO[bounded]
        p_CO = (R_CB[rows] @ self._p_BO[bounded])[:, :, 0] + p_CB[rows]
        inside = self._frustum.overlaps(p_CO, R_CO, self._half[bounded])
        view = np.concatenate([bounded[inside], self._unbounded])
        return view, R_CO[inside], p_CO[inside]

    def _image_rectangles(
        self, view: np.ndarray, R_CO: np.ndarray, p_CO: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The image rectangles [low, high] of the geometries ``view`` (from their
        box's corners, clipped to the image; the whole image if a corner is not in
        front) and their depth ranges [depth_min, depth_max]."""
        boxed = len(view) - len(self._unbounded)
        corners = (_BOX_CORNERS * self._half[view[:boxed], None, :]) @ R_CO.transpose(0, 2, 1)
        corners += p_CO[:, None, :]
        depth = corners[:, :, 0]
        depth_min = np.concatenate([depth.min(axis=1), np.zeros(len(self._unbounded))])
        depth_max = np.concatenate([depth.max(axis=1), np.full(len(self._unbounded), np.inf)])
        low = np.empty((len(view), 2))
        high = np.empty((len(view), 2))
        low[:], high[:] = self._image_low, self._image_high
        front = np.flatnonzero(depth_min[:boxed] > 1e-9)
        image = corners[front, :, 1:] / depth[front, :, None]
        low[front] = np.maximum(low[front], image.min(axis=1))
        high[front] = np.minimum(high[front], image.max(axis=1))
        return low, high, depth_min, depth_max

    @staticmethod
    def _pairs_to_test(
        own: np.ndarray, low: np.ndarray, high: np.ndarray, depth_min: np.ndarray, depth_max: np.ndarray
    ) -> Optional[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """The (model, geometry) pairs to cast rays against, by model, its own geometries first.

        Model i = seen[i] owns the geometries own[i]: its rectangle [lo, hi], its
        farthest point, and the other geometries that may hide it. Returns
        (model, geometry, mine: the geometry is the model's, lo, hi), or None
        when no model has rays to cast.
        """
        lo = np.where(own[:, :, None], low, np.inf).min(axis=1)
        hi = np.where(own[:, :, None], high, -np.inf).max(axis=1)
        farthest = np.where(own, depth_max, -np.inf).max(axis=1)
        others = (
            ~own
            & (low < hi[:, None]).all(axis=2)
            & (high > lo[:, None]).all(axis=2)
            & (depth_min < farthest[:, None])
        )
        cast = own.any(axis=1) & (lo < hi).all(axis=1)
        model, geometry = np.nonzero((own | others) & cast[:, None])
        if not len(model):
            return None
        mine = own[model, geometry]
        order = np.lexsort((~mine, model))
        return model[order], geometry[order], mine[order], lo, hi

    def _pair_slabs(
        self, view: np.ndarray, geometry: np.ndarray, R_CB: np.ndarray, p_CB: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The slabs of each pair's geometry ``view[geometry]``, in C (one run per
        pair): n_C = R_CB n_B and d_C = d_B +- n_C . p_CB.

        Returns (count, runs: each pair's slab count and first row, n, d_plus, d_minus).
        """
        count = self._slab_counts[view[geometry]]
        runs = np.cumsum(count) - count
        first_slab = self._slab_start[view[geometry]]
        slabs = np.arange(count.sum()) - np.repeat(runs - first_slab, count)
        body = self._body_row[self._slab_geometry[slabs]]
        n = (R_CB[body] @ self._normals[slabs, :, None])[:, :, 0]
        shift = (n * p_CB[body]).sum(axis=1)
        d_plus = self._d_plus[slabs] + shift
        d_minus = self._d_minus[slabs] - shift
        return count, runs, n, d_plus, d_minus

    def _ray_depths(
        self,
        view: np.ndarray,
        model: np.ndarray,
        geometry: np.ndarray,
        lo: np.ndarray,
        hi: np.ndarray,
        R_CB: np.ndarray,
        p_CB: np.ndarray,
    ) -> np.ndarray:
        """(rays, pairs): the depth of the first surface of each pair's geometry
        that each of its model's rays meets between near and far (inf: none)."""
        count, runs, n, d_plus, d_minus = self._pair_slabs(view, geometry, R_CB, p_CB)
        # Model m's rays are (1, y, z) with (y, z) = lo_m + g (hi_m - lo_m) for the
        # grid points g: a = n . (1, y, z) = (n_x + n_yz . lo_m) + (n_yz * (hi_m - lo_m)) . g.
        # Arrays below are (rays, slabs) or (rays, pairs).
        m = np.repeat(model, count)
        coefficients = np.concatenate(
            [n[:, :1] + (n[:, 1:] * lo[m]).sum(axis=1, keepdims=True), n[:, 1:] * (hi[m] - lo[m])], axis=1
        )
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inverse = 1.0 / (self._grid_columns @ coefficients.T)  # 1 / a
            ends = d_plus * inverse, -d_minus * inverse
            t_in = np.maximum.reduceat(np.minimum(*ends), runs, axis=1)
            t_out = np.minimum.reduceat(np.maximum(*ends), runs, axis=1)
        # The first surface at depth >= near: the entry, or the exit if the entry is clipped.
        surface = np.where(t_in >= self._near, t_in, t_out)
        return np.where((t_in <= t_out) & (surface >= self._near) & (surface <= self._far), surface, np.inf)


@dataclass(frozen=True)
class _Candidate:
    """A model the camera may report, as it reports it."""

    name: str  # "" when anonymized
    type: str
    origin_body: int  # body index of M
    instance: int  # model instance index


# ----------------------------------------------------------------------------
# The system


class LogicalCamera(LeafSystem):
    """Reports the models of a MultibodyPlant that overlap a view frustum.

    .. pydrake_system::

        name: LogicalCamera
        input_ports:
        - body_poses
        output_ports:
        - image

    - ``body_poses`` (abstract ``list[RigidTransform]``): the plant's
      ``get_body_poses_output_port()``, X_WB of every body by body index.
    - ``image`` (abstract :class:`LogicalCameraImage`): the last sample. The
      camera samples at ``config.update_rate_hz`` from t = 0 (and at
      initialization), and holds the sample in between: at t = 0.25 with
      10 Hz the image's time is 0.2. Before the context is initialized the
      image is empty with time NaN. A forced event (``ExecuteForcedEvents``)
      captures an image at the context's time on demand.

    Frames: the camera frame C is the plant frame ``frame``; it looks along +Cx,
    +Cz up, the width along Cy (Gazebo's logical camera; see the module
    docstring and :func:`X_CameraOptical` for the optical frame).

    Frustum: the truncated pyramid between the planes x = near and x = far of
    C, with half-width x tan(fov / 2) along Cy and half-height
    x tan(fov / 2) / aspect_ratio along Cz.

    Candidates: every model instance of the plant except world, default and
    ``exclude`` (the camera's own model), that has geometry (proximity or
    illustration) and passes ``known_types`` / ``known_names``. A model with a
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
    over the model's image rectangle (:class:`_RayCastOcclusion`), so a far,
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
        config.validate()
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
        self._frustum = _FrustumOverlap(config)
        self._init_candidates(plant, scene_graph_inspector, {int(i) for i in exclude})
        # The one variant point: how much of each model in view is visible.
        self._visibility: _AllVisible | _RayCastOcclusion = (
            _RayCastOcclusion(
                plant, scene_graph_inspector, config, {c.instance: k for k, c in enumerate(self._candidates)}
            )
            if config.occlusion
            else _AllVisible()
        )

        self.DeclareAbstractInputPort("body_poses", plant.get_body_poses_output_port().Allocate())
        period = 1.0 / config.update_rate_hz
        self._image = self.DeclareAbstractState(
            AbstractValue.Make(
                LogicalCameraImage(time=math.nan, camera_name=config.name, X_WC=RigidTransform(), models=())
            )
        )
        # Fault injection: no new images before this time (see black_out()).
        self._blackout = self.DeclareDiscreteState(np.array([-math.inf]))
        self.DeclareInitializationUnrestrictedUpdateEvent(self._update)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, 0.0, self._update)
        self.DeclareForcedUnrestrictedUpdateEvent(self._update)
        self.DeclareStateOutputPort("image", self._image)

    def _init_candidates(
        self, plant: MultibodyPlant, inspector: SceneGraphInspector, exclude: set[int]
    ) -> None:
        """Sets the candidate models and the bounding boxes of their bodies
        (rows of ``_box_*``; candidate k owns rows [_box_starts[k], _box_starts[k + 1]))."""
        config = self._config
        candidates: list[_Candidate] = []
        box_body: list[int] = []
        box_centre: list[np.ndarray] = []
        box_half: list[np.ndarray] = []
        box_starts: list[int] = []
        for i in range(plant.num_model_instances()):
            instance = ModelInstanceIndex(i)
            name = plant.GetModelInstanceName(instance)
            if (
                i in _RESERVED_INSTANCES
                or i in exclude
                or (config.known_types and model_type(name) not in config.known_types)
                or (config.known_names and name not in config.known_names)
            ):
                continue
            bodies = plant.GetBodyIndices(instance)
            boxes = []
            for body in bodies:
                geometries = _geometries(plant, inspector, body)
                if geometries:
                    boxes.append((int(body), _bounding_box(inspector, geometries)))
            if not boxes:
                continue
            bounded = [(body, box) for body, box in boxes if box is not None]
            if len(bounded) < len(boxes):
                _log.debug("%s: model %r has a HalfSpace; never reported", self._name, name)
                continue
            candidates.append(
                _Candidate("" if config.anonymize else name, model_type(name), int(bodies[0]), i)
            )
            box_starts.append(len(box_body))
            for body, (centre, half) in bounded:
                box_body.append(body)
                box_centre.append(centre)
                box_half.append(half)
        self._candidates = tuple(candidates)
        self._box_body = tuple(box_body)
        self._box_centre = np.array(box_centre).reshape(-1, 3, 1)
        self._box_half = np.array(box_half).reshape(-1, 3)
        self._box_starts = np.array(box_starts, dtype=np.intp)
        _log.debug("%s: %d candidate models, %d boxes", self._name, len(candidates), len(box_body))

    @property
    def config(self) -> LogicalCameraConfig:
        """A copy of the camera's configuration."""
        return copy.deepcopy(self._config)

    def _update(self, context: Context, state: State) -> None:
        if context.get_time() < context.get_discrete_state(self._blackout)[0]:
            return  # blacked out: the last image is held (it goes stale)
        state.get_mutable_abstract_state(self._image).set_value(self._capture(context))

    def black_out(self, context: Context, until: float) -> None:
        """Fault injection: the camera publishes no new image before ``until``
        (its output keeps the last image, whose time shows it is stale)."""
        context.SetDiscreteState(self._blackout, np.array([float(until)]))

    def _capture(self, context: Context) -> "LogicalCameraImage":
        """The image at the context's time."""
        time = context.get_time()
        X_WB = self.get_input_port(0).Eval(context)
        X_WC = X_WB[self._camera_body] @ self._X_BC
        occlusion = self._visibility.occlusion
        if not self._candidates:
            return LogicalCameraImage(time, self._name, X_WC, (), occlusion)
        X_CW = X_WC.inverse()
        T_CW = X_CW.GetAsMatrix34()
        # [R_CB | R_CW p_WB] of the bodies with boxes, then the box centres in C.
        T = T_CW[:, :3] @ np.array([X_WB[b].GetAsMatrix34() for b in self._box_body])
        R_CB = T[:, :, :3]
        p_CB = T[:, :, 3] + (R_CB @ self._box_centre)[:, :, 0] + T_CW[:, 3]
        seen = np.logical_or.reduceat(self._frustum.overlaps(p_CB, R_CB, self._box_half), self._box_starts)
        indices = np.flatnonzero(seen)
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
                X_CM = RigidTransform(
                    RollPitchYaw(noise[k, 3:]).ToRotationMatrix() @ X_CM.rotation(),
                    X_CM.translation() + noise[k, :3],
                )
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
    builder.Connect(plant.get_body_poses_output_port(), camera.get_input_port(0))
    return camera
