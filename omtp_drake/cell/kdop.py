"""Every geometry as a convex polytope of slabs, for ray casting: exact for a box
or a half-space, a 26-DOP (the tightest polytope with 26 fixed face normals)
otherwise (:func:`slabs_in_geometry_frame`). Frames: ``G`` the geometry's frame.
"""

from __future__ import annotations

import numpy as np
from pydrake.geometry import (
    Box,
    Capsule,
    Convex,
    Cylinder,
    Ellipsoid,
    GeometryId,
    HalfSpace,
    Mesh,
    SceneGraphInspector,
    Sphere,
)

from omtp_drake.cell.body_geometry import oriented_bounding_box, per_mesh_file
from omtp_drake.errors import ConfigError

#: The 13 slab directions of a 26-DOP: the 3 axes, the 6 face diagonals and the
#: 4 body diagonals (unit vectors).
_DOP_DIRECTIONS = np.array(
    [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1], [0, 1, 1],
     [0, 1, -1], [1, 1, 1], [1, 1, -1], [1, -1, 1], [1, -1, -1]],
    float,
)  # fmt: skip
_DOP_DIRECTIONS /= np.linalg.norm(_DOP_DIRECTIONS, axis=1, keepdims=True)


def slabs_in_geometry_frame(
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

        return per_mesh_file("dop", inspector, geometry_id, hull_slabs)
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
        obb = oriented_bounding_box(inspector, geometry_id)
        if obb is None:  # (only a HalfSpace is unbounded, handled above)
            raise ConfigError(f"geometry {inspector.GetName(geometry_id)!r} has no bounding box")
        axes = obb.pose().rotation().matrix().T  # rows: the box's axes in G
        centre = axes @ obb.pose().translation()
        return axes, obb.half_width() + centre, obb.half_width() - centre
    return n, h, h
