"""A bin of mesh collisions (the course's own bin: ``bin_bottom.dae`` + ``bin_sides.dae``),
loaded as the student's file writes it.

Gazebo collides with a collision mesh's triangles, so the course's bin is open there;
Drake's point contact would collide with each mesh's convex hull, a closed block. Such a
bin is the student's own model entry, its collision meshes loaded as convex pieces that
keep it open (``ModelConfig.open_links``: :func:`omtp_drake.assets.convex_piece_files`).
Its inside, for the cell's in-bin test and drop slots, is measured here on the very
triangles its collisions have (:func:`mesh_bin_walls`): rays from the bin's axis.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.assets import drake_mesh, mesh_source
from omtp_drake.convex_pieces import ray_distance
from omtp_drake.errors import ConfigError
from omtp_drake.launch.urdf_model import UrdfModel


def has_mesh_collision(model: UrdfModel, link: str) -> bool:
    """Whether a collision of ``link`` is a mesh."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    return element is not None and element.find("collision/geometry/mesh") is not None


def mesh_bin_walls(
    model: UrdfModel, link: str, packages: Mapping[str, str], where: str, kind: str = "collision"
) -> list[float] | None:
    """``[inner half length along x, along y, floor top, rim height]`` (m, in the link's
    frame) of a bin whose collisions (``kind``: or visuals) are meshes (and boxes): the
    rim is their highest point, the floor the first surface a ray down the link's z axis
    meets, the walls the first ones rays along +-x and +-y meet halfway up (the nearer of
    each pair). None when one is another shape or its mesh cannot be read, or a ray meets
    nothing."""
    triangles = _shape_triangles(model, link, packages, where, kind)
    if triangles is None or not len(triangles):
        return None
    rim = float(triangles[..., 2].max())
    down = ray_distance(triangles, [0.0, 0.0, rim + 1.0], [0.0, 0.0, -1.0])
    if down is None:
        return None
    floor_top = rim + 1.0 - down
    middle = [0.0, 0.0, (floor_top + rim) / 2]
    halves = []
    for axis in (0, 1):
        hits = [ray_distance(triangles, middle, sign * np.eye(3)[axis]) for sign in (1, -1)]
        if None in hits:
            return None
        halves.append(min(h for h in hits if h is not None))
    if not (halves[0] > 0 and halves[1] > 0 and floor_top < rim):
        return None
    return [round(float(v), 9) for v in (*halves, floor_top, rim)]


def _shape_triangles(
    model: UrdfModel, link: str, packages: Mapping[str, str], where: str, kind: str
) -> np.ndarray | None:
    """The triangles (k x 3 x 3, link frame) of ``link``'s ``kind`` elements (collision or
    visual), as Drake loads them (read from the converted ``.obj``: no mesh library is
    imported for a mesh converted before)."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    out = []
    for collision in element.findall(kind) if element is not None else []:
        geometry = collision.find("geometry")
        box = geometry.find("box") if geometry is not None else None
        mesh = geometry.find("mesh") if geometry is not None else None
        try:
            X = _origin(collision)
            if box is not None:
                triangles = _box_triangles([float(v) for v in box.get("size", "").split()])
            elif mesh is not None:
                src, _ = mesh_source((mesh.get("filename") or "").strip(), packages, where)
                if src is None:
                    return None
                scale = np.array([float(v) for v in mesh.get("scale", "1 1 1").split()])
                triangles = _obj_triangles(drake_mesh(src, collision=True)) * scale
            else:
                return None
        except (ValueError, OSError, ConfigError):
            return None
        out.append(X.multiply(triangles.reshape(-1, 3).T).T.reshape(-1, 3, 3))
    return np.concatenate(out) if out else None


def _box_triangles(size: list[float]) -> np.ndarray:
    """The 12 triangles of a box of ``size`` about its centre."""
    if len(size) != 3:
        raise ValueError(f"box size {size}")
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * np.array(size) / 2
    quads = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))
    return np.array([corners[[q[0], q[i], q[i + 1]]] for q in quads for i in (1, 2)])


def _obj_triangles(path: Path) -> np.ndarray:
    """The triangles of the Wavefront ``.obj`` file ``path`` (its ``v`` and ``f`` lines;
    polygons as fans)."""
    vertices, faces = [], []
    for line in path.read_text().splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            vertices.append([float(v) for v in words[1:4]])
        elif words[0] == "f":
            index = [int(w.split("/")[0]) for w in words[1:]]
            faces += [(index[0], index[i], index[i + 1]) for i in range(1, len(index) - 1)]
    points = np.array(vertices, dtype=float).reshape(-1, 3)
    rows = np.array(faces, dtype=int).reshape(-1, 3)
    rows = np.where(rows > 0, rows - 1, rows + len(points))  # (1-based; negative: from the end)
    return points[rows]


def _origin(element) -> RigidTransform:
    origin = element.find("origin")
    xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
    rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
    return RigidTransform(RollPitchYaw(rpy), xyz)
