"""The logical camera's occlusion: the visible fraction of each model in view.

:class:`RayCastOcclusion` casts rays against every visual geometry as a convex
polytope (:mod:`omtp_drake.cell.kdop`); :class:`AllVisible` stands in when the
camera does not test occlusion. Frames as in :mod:`omtp_drake.cell.logical_camera`
(``C`` the camera, ``W`` the world, ``B`` a body, ``G`` a geometry, ``O`` an
oriented bounding box).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Optional

import numpy as np
from pydrake.geometry import SceneGraphInspector
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex

from omtp_drake.cell.body_geometry import BOX_CORNERS, oriented_bounding_box, seen_geometries
from omtp_drake.cell.frustum import FrustumOverlap
from omtp_drake.cell.kdop import slabs_in_geometry_frame
from omtp_drake.scenario.camera import LogicalCameraConfig

#: Rays per side of the grid cast over each model's image rectangle: 16 x 16 =
#: 256 rays, so a model's visible fraction is resolved to about 1 / 16 along an
#: occluding edge whatever its size in the image (bench/bench_occlusion.py).
OCCLUSION_GRID = 16


class AllVisible:
    """Visibility without occlusion: every model in view is fully visible (no work)."""

    occlusion = False

    def fractions(self, T_CW: np.ndarray, X_WB: Sequence[RigidTransform], seen: np.ndarray) -> np.ndarray:
        return np.ones(len(seen))


class RayCastOcclusion:
    """The visible fraction of models, from rays cast against the scene's visual
    geometry (see :class:`~omtp_drake.cell.logical_camera.LogicalCamera`, "Occlusion").

    Every visual geometry of the plant (:func:`~omtp_drake.cell.body_geometry.seen_geometries`: its
    perception geometries, else illustration, else proximity ones) is a convex
    polytope fixed to its body (:func:`slabs_in_geometry_frame`), with the
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
        self._frustum = FrustumOverlap(config)
        ty = math.tan(config.horizontal_fov / 2)
        self._image_low = np.array([-ty, -ty / config.aspect_ratio])
        self._image_high = -self._image_low
        bodies: list[int] = []
        owner, body_row, R_BO, p_BO, half = [], [], [], [], []
        normals, d_plus, d_minus, counts = [], [], [], []
        for index in range(plant.num_bodies()):
            body = plant.get_body(BodyIndex(index))
            geometries = seen_geometries(plant, inspector, body.index())
            if not geometries:
                continue
            bodies.append(index)
            for geometry_id in geometries:
                X_BG = inspector.GetPoseInFrame(geometry_id)
                n_G, plus, minus = slabs_in_geometry_frame(inspector, geometry_id)
                n_B = n_G @ X_BG.rotation().matrix().T
                shift = n_B @ X_BG.translation()  # n_B . p_B = n_G . p_G + n_B . p_BG
                normals.append(n_B)
                d_plus.append(plus + shift)
                d_minus.append(minus - shift)
                counts.append(len(n_B))
                obb = oriented_bounding_box(inspector, geometry_id)  # None: unbounded
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
        corners = (BOX_CORNERS * self._half[view[:boxed], None, :]) @ R_CO.transpose(0, 2, 1)
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
