"""A triangle mesh as convex pieces that keep it open: the skin of its flat faces.

Drake's point contact collides with a collision mesh's convex hull, so an open bin
given as one mesh would be a closed block. :func:`convex_pieces` cuts a mesh made of
flat faces (a bin, a tray, a shelf: what CAD tools export) into convex pieces whose
union is the mesh's skin (a closed convex part of the mesh, a floor plate, is its own piece):

1. the triangles are grouped by the plane they lie in, and the triangles of one plane
   that share edges are merged, greedily, into convex polygons (a triangle joins a
   polygon only when the polygon stays convex: a rim ring becomes four bands, not a lid);
2. each polygon is extruded behind its face (against its outward normal) into a slab:
   as deep as the solid is there (the nearest face behind it, by rays from the polygon),
   at most ``max_depth``. In a closed solid (a wall with a thickness) every slab lies
   inside the solid; a face with nothing behind it (an open, zero-thickness surface) is
   extruded ``max_depth`` on the side away from the mesh's centre (outward of a bin).

The pieces are exact for solids bounded by flat faces (each slab is the prism under a
face); curved faces are approximated by their facets. ``ray_distance`` is the
ray-triangle test both this and the bins' inner walls (:mod:`omtp_drake.launch.mesh_bins`)
use.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from pathlib import Path

import numpy as np

#: The deepest slab (m of the mesh file) of a piece behind its face: a floor or wall that
#: thick stops a part that falls onto it for a 10 ms step.
PIECE_DEPTH = 0.05
#: Relative area tolerance of the convexity test of a merged polygon.
_AREA_TOL = 1e-6
#: Rounding (in the mesh's units) of plane normals and offsets when grouping coplanar faces.
_NORMAL_DECIMALS, _OFFSET_DECIMALS = 4, 5
#: The thinnest slab (a solid thinner than this behind a face is given this depth).
_MIN_DEPTH = 1e-4


def convex_pieces(vertices, faces, *, max_depth: float) -> list[np.ndarray]:
    """The convex pieces (each an array of points; its convex hull is the piece) of the
    triangle mesh ``vertices`` (n x 3) / ``faces`` (m x 3 indices), see the module doc."""
    import trimesh

    mesh = trimesh.Trimesh(np.asarray(vertices, float), np.asarray(faces, int), process=True)
    mesh.remove_unreferenced_vertices()
    pieces: list[np.ndarray] = []
    centre = mesh.vertices.mean(axis=0) if len(mesh.vertices) else np.zeros(3)
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, node_count=len(mesh.faces))
    for label in np.unique(labels):
        body = trimesh.Trimesh(mesh.vertices, mesh.faces[labels == label], process=False)
        body.remove_unreferenced_vertices()
        closed = bool(body.is_watertight)
        if closed and body.is_convex:  # (a floor plate: itself, as deep as it is)
            pieces.append(np.asarray(body.vertices))
            continue
        triangles = body.vertices[body.faces]
        for polygon, normal, members in _convex_polygons(body):
            if closed:  # outward (whichever way its triangles wind): behind it is the solid
                normal = normal if _outside(triangles, polygon.mean(axis=0), normal) else -normal
                depth = _depth_behind(polygon, normal, np.delete(triangles, members, axis=0), max_depth)
            else:
                outward = normal if np.dot(polygon.mean(axis=0) - centre, normal) >= 0 else -normal
                normal, depth = -outward, max_depth  # (extruded along outward)
            pieces.append(np.vstack([polygon, polygon - max(depth, _MIN_DEPTH) * normal]))
    return pieces


def _convex_polygons(mesh) -> list[tuple[np.ndarray, np.ndarray, list[int]]]:
    """Each convex polygon of coplanar, edge-sharing triangles: its corner points (3D),
    its unit normal and its triangles' indices."""
    normals, triangles = mesh.face_normals, mesh.vertices[mesh.faces]
    offsets = np.einsum("ij,ij->i", normals, triangles[:, 0])
    planes: dict[tuple, list[int]] = defaultdict(list)
    for i, (n, d) in enumerate(zip(normals, offsets)):
        if np.linalg.norm(n) > 0.5:  # (a degenerate triangle has a zero normal)
            sign = 1.0 if n[np.argmax(np.abs(n) > 1e-6)] > 0 else -1.0  # (either way round)
            planes[(*np.round(sign * n, _NORMAL_DECIMALS), round(sign * float(d), _OFFSET_DECIMALS))].append(
                i
            )
    edges: dict[tuple[int, int], list[int]] = defaultdict(list)
    for i, face in enumerate(mesh.faces):
        for a, b in ((0, 1), (1, 2), (2, 0)):
            edges[_edge(face[a], face[b])].append(i)
    out = []
    for (*key, _), members in planes.items():
        normal = np.asarray(key, float) / np.linalg.norm(key)
        u = np.cross(normal, [1.0, 0, 0] if abs(normal[0]) < 0.9 else [0, 1.0, 0])
        u /= np.linalg.norm(u)
        basis = np.array([u, np.cross(normal, u)])
        left = set(members)
        flat = triangles @ basis.T
        while left:
            polygon = _grow(min(left), left, mesh.faces, edges, flat)
            points = triangles[polygon].reshape(-1, 3)
            hull = _hull_2d(points @ basis.T)
            out.append((points[hull], normal, polygon))
    return out


def _grow(seed: int, left: set[int], faces, edges, flat) -> list[int]:
    """The triangles merged with ``seed`` (taken out of ``left``): neighbours across an
    edge in the same plane, each kept only when the union stays convex."""
    polygon, area, corners = [seed], _area_2d(flat[seed]), flat[seed]
    left.discard(seed)
    frontier = [seed]
    while frontier:
        face = faces[frontier.pop()]
        for a, b in ((0, 1), (1, 2), (2, 0)):
            for other in edges[_edge(face[a], face[b])]:
                if other not in left:
                    continue
                points = np.vstack([corners, flat[other]])
                hull = points[_hull_2d(points)]
                hull_area, extra = _area_2d(hull), _area_2d(flat[other])
                if abs(hull_area - area - extra) <= _AREA_TOL * max(hull_area, 1e-12) + 1e-15:
                    polygon.append(other)
                    area, corners = area + extra, hull
                    left.discard(other)
                    frontier.append(other)
    return polygon


def _edge(a, b) -> tuple[int, int]:
    """An edge between two vertex indices, either way round."""
    return (int(a), int(b)) if a < b else (int(b), int(a))


def _hull_2d(points: np.ndarray) -> list[int]:
    """Indices of the convex hull's corners of 2D ``points``, counter-clockwise (monotone chain)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))

    def cross(o, a, b) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    lower: list[int] = []
    upper: list[int] = []
    for chain, indices in ((lower, order), (upper, order[::-1])):
        for i in indices:
            while len(chain) >= 2 and cross(points[chain[-2]], points[chain[-1]], points[i]) <= 1e-15:
                chain.pop()
            chain.append(i)
    return lower[:-1] + upper[:-1]


def _area_2d(points: np.ndarray) -> float:
    """The area of the polygon ``points`` (2D, in order; a triangle in any order)."""
    x, y = points[:, 0], points[:, 1]
    return abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))) / 2


def _depth_behind(polygon: np.ndarray, normal: np.ndarray, others: np.ndarray, max_depth: float) -> float:
    """How deep the solid is behind ``polygon`` (rays against its normal from its centre
    and from its corners pulled a tenth towards it), at most ``max_depth``."""
    centre = polygon.mean(axis=0)
    starts = [centre, *(c + 0.1 * (centre - c) for c in polygon)]
    depth = max_depth
    for start in starts:
        hit = ray_distance(others, start, -normal)
        if hit is not None and hit > 1e-9:
            depth = min(depth, hit)
    return depth


def _outside(triangles: np.ndarray, point: np.ndarray, normal: np.ndarray) -> bool:
    """Whether ``normal`` at ``point`` of the closed mesh ``triangles`` points out of it: a
    ray from just in front of the point, nearly along it (off the mesh's edges), leaves
    the solid an even number of times."""
    size = float(np.ptp(triangles.reshape(-1, 3), axis=0).max())
    direction = normal + np.array([2**0.5, 3**0.5, 5**0.5]) * 1e-3
    hits = _ray_hits(triangles, point + 1e-6 * size * normal, direction / np.linalg.norm(direction))
    return len(hits) % 2 == 0


def ray_distance(triangles: np.ndarray, origin, direction) -> float | None:
    """The distance along the unit ``direction`` from ``origin`` to the nearest of
    ``triangles`` (k x 3 x 3) the ray meets in front of it (Moller-Trumbore), or None."""
    hits = _ray_hits(triangles, origin, direction)
    return float(hits.min()) if len(hits) else None


def _ray_hits(triangles: np.ndarray, origin, direction) -> np.ndarray:
    """The distances along the ray to each of ``triangles`` it meets in front of ``origin``."""
    if len(triangles) == 0:
        return np.zeros(0)
    origin, direction = np.asarray(origin, float), np.asarray(direction, float)
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    e1, e2 = b - a, c - a
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origin - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ direction) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    tol = 1e-9
    hit = ok & (u >= -tol) & (v >= -tol) & (u + v <= 1 + tol) & (t > 1e-9)
    return t[hit]


def axis_box(points: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(centre, size)`` when the convex hull of ``points`` is a box along the mesh's axes
    (the slabs of a box-like mesh are: Drake's box contact is its sturdiest), else None."""
    import trimesh

    low, high = points.min(axis=0), points.max(axis=0)
    size = high - low
    volume = float(np.prod(size))
    if volume <= 0 or abs(trimesh.convex.convex_hull(points).volume - volume) > 1e-6 * volume:
        return None
    return (low + high) / 2, size


def write_pieces(obj: Path, index: Path, write: Callable[[Path, bytes], None]) -> None:
    """Cuts the mesh file ``obj`` into its :func:`convex_pieces` (``max_depth``:
    ``PIECE_DEPTH``), each written with ``write`` as ``K.obj`` beside ``index``, which lists
    them: a line per piece, its file and, for a box along the mesh's axes (:func:`axis_box`),
    its centre and size."""
    import trimesh

    mesh = trimesh.load(str(obj), force="mesh")
    lines = []
    for k, points in enumerate(convex_pieces(mesh.vertices, mesh.faces, max_depth=PIECE_DEPTH)):
        write(index.parent / f"{k}.obj", trimesh.convex.convex_hull(points).export(file_type="obj").encode())
        box = axis_box(points)
        lines.append(
            " ".join([f"{k}.obj", *(repr(float(v)) for v in (*box[0], *box[1]))] if box else [f"{k}.obj"])
        )
    write(index, "\n".join(lines).encode())
