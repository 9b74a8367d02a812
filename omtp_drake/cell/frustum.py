"""The logical camera's view frustum: which oriented boxes overlap it.

:class:`FrustumOverlap` is the exact overlap test of oriented boxes against the
frustum (separating axes). Frames as in :mod:`omtp_drake.cell.logical_camera`
(``C`` the camera, ``B`` a box).
"""

from __future__ import annotations

import math

import numpy as np

from omtp_drake.scenario.camera import LogicalCameraConfig


class FrustumOverlap:
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
        # A row vector a times this (3, 21) matrix = the rows a, e_0 x a, ..., e_5 x a
        # (np.cross(e, I) is the transpose of e's cross-product matrix: a @ it = e x a).
        self._axis_rows = np.concatenate([np.eye(3)] + [np.cross(e, np.eye(3)) for e in edges], axis=1)

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
        distance = self.face_distances(p_CB)
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
            inside = (self.face_distances(vertex) <= 0).all(axis=1)
            result[undecided[inside]] = True
            rest = undecided[~inside]
            if len(rest):
                result[rest] = self.not_separated_by_edges_or_box(p_CB[rest], R_CB[rest], half[rest])
        return result

    def face_distances(self, p_C: np.ndarray) -> np.ndarray:
        """n_k . p - b_k for points p (n, 3) in C and the six faces (near, far,
        +y, -y, +z, -z): (n, 6), > 0 where p is outside that face."""
        return p_C @ self._face_normals.T - self._face_offsets

    def not_separated_by_edges_or_box(
        self, p_CB: np.ndarray, R_CB: np.ndarray, half: np.ndarray
    ) -> np.ndarray:
        """The last stage of :meth:`overlaps` on its own: no box face normal nor
        frustum-edge x box-edge cross product separates the boxes (arguments as
        :meth:`overlaps`; the frustum's face normals are not tried here)."""
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
