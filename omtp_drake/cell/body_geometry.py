"""Which geometries of a body a camera counts, and the boxes that bound them.

* :func:`body_geometries` (those of given roles; by default proximity and
  illustration: the bodies a logical camera may report) and
  :func:`seen_geometries` (what a camera sees of a body: one role, the first of
  perception, illustration, proximity that it has).
* :func:`bounding_box`: the axis-aligned box of a body's geometries' oriented
  bounding boxes (:func:`oriented_bounding_box`).

A mesh's bounding box (and, through :func:`per_mesh_file`, its convex hull) is
computed once per file and scale (a memo of pure functions of the file, kept on
disk as well). Frames
as in :mod:`omtp_drake.cell.logical_camera` (``B`` a body, ``G`` a geometry,
``O`` an oriented bounding box).
"""

from __future__ import annotations

import hashlib
import logging
import pickle
import threading
from collections import OrderedDict
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Optional, TypeVar

import numpy as np
from pydrake.geometry import Convex, GeometryId, Mesh, Obb, Role, SceneGraphInspector
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex

from omtp_drake.assets import cache_entry, write_atomic

_log = logging.getLogger(__name__)


def body_geometries(
    plant: MultibodyPlant,
    inspector: SceneGraphInspector,
    body_index: BodyIndex,
    roles: Sequence[Role] = (Role.kProximity, Role.kIllustration),
) -> list[GeometryId]:
    """The geometries of a body that have any of ``roles`` (by default those a
    logical camera may report), in id order."""
    frame_id = plant.GetBodyFrameIdIfExists(body_index)
    if frame_id is None:
        return []
    geometries: set[GeometryId] = set()
    for role in roles:
        geometries |= set(inspector.GetGeometries(frame_id, role))
    return sorted(geometries, key=lambda g: g.get_value())


def seen_geometries(
    plant: MultibodyPlant, inspector: SceneGraphInspector, body_index: BodyIndex
) -> list[GeometryId]:
    """What a camera sees of a body: its perception geometries, else its
    illustration ones, else its proximity ones (a body modelled for one role only
    is still seen)."""
    for role in (Role.kPerception, Role.kIllustration, Role.kProximity):
        geometries = body_geometries(plant, inspector, body_index, roles=(role,))
        if geometries:
            return geometries
    return []


T = TypeVar("T")

#: What is computed from a mesh file, by (what, file, scale): a mesh's bounding box
#: and convex hull take milliseconds each (a UR arm's hulls about 0.25 s in all), and
#: every camera of every station needs those of every arm. Pure functions of the
#: file, so a memo, not state: in the process, and on disk beside the converted
#: models (:func:`~omtp_drake.assets.cache_entry`), so that each new process (a
#: ``ros-run``, a batch run, a graded script) does not compute them again (the
#: first station build of a process: figures in bench/README.md, "Measured").
_MESH_MEMO: dict[tuple[str, str, tuple[float, ...]], Any] = {}


def per_mesh_file(
    what: str, inspector: SceneGraphInspector, geometry_id: GeometryId, compute: Callable[[], T]
) -> T:
    """``compute()``, once per mesh file and scale for a Mesh or Convex from a file."""
    shape = inspector.GetShape(geometry_id)
    if not (isinstance(shape, (Mesh, Convex)) and shape.source().is_path()):
        return compute()
    key = (what, f"{type(shape).__name__}:{shape.source().path()}", tuple(shape.scale3()))
    if key not in _MESH_MEMO:
        _MESH_MEMO[key] = _on_disk(key, Path(shape.source().path()), compute)
    return _MESH_MEMO[key]


def _on_disk(key: tuple, mesh: Path, compute: Callable[[], T]) -> T:
    """``compute()``'s value for ``key`` from the disk memo, or computed and stored
    there. The file's name hashes the key with the mesh's size and modification
    time, so an edited mesh is computed again; an unreadable entry too."""
    try:
        stat = mesh.stat()
        digest = hashlib.sha1(repr((key, stat.st_size, stat.st_mtime_ns)).encode()).hexdigest()
        path = cache_entry(f"mesh_facts/{key[0]}-{digest}.pickle")
    except OSError:  # no mesh file, or a read-only cache without a folder for it
        return compute()
    try:
        return pickle.loads(path.read_bytes())
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ValueError):
        pass
    value = compute()
    try:
        write_atomic(path, pickle.dumps(value))
    except OSError as error:  # a read-only cache: computed every time, as before
        _log.debug("mesh facts not cached (%s)", error)
    return value


def oriented_bounding_box(inspector: SceneGraphInspector, geometry_id: GeometryId) -> Optional[Obb]:
    """The geometry's oriented bounding box in its frame (None: unbounded), computed
    once per mesh file and scale."""
    return per_mesh_file("obb", inspector, geometry_id, lambda: inspector.GetObbInGeometryFrame(geometry_id))


#: The 8 corners of the cube [-1, 1]^3 (rows).
BOX_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)


#: Boxes by their geometries' ids, the newest :data:`_BOXES_KEPT`. A memo of a pure
#: function, not state: a GeometryId is never reused in a process, and a geometry's shape
#: and pose in its frame are fixed once registered. Each camera of a station asks for the
#: same bodies' boxes (a logical camera's candidates, the course plugin's view): six times
#: a body in a three-camera cell, an eighth of a short ros-run's CPU before.
_BOXES: OrderedDict[tuple[int, ...], Optional[tuple[np.ndarray, np.ndarray]]] = OrderedDict()
_BOXES_KEPT = 4096
_BOXES_LOCK = threading.Lock()


def bounding_box(
    inspector: SceneGraphInspector, geometries: Sequence[GeometryId]
) -> Optional[tuple[np.ndarray, np.ndarray]]:
    """The axis-aligned box (centre, half-extents), in the frame F they are
    registered to, of the oriented bounding boxes of ``geometries`` (analytic
    for primitives, from the vertices for meshes); None if one of them is
    unbounded (a HalfSpace). The arrays are read-only (shared by every caller)."""
    key = tuple(g.get_value() for g in geometries)
    with _BOXES_LOCK:
        if key in _BOXES:
            _BOXES.move_to_end(key)
            return _BOXES[key]
    box = _bounding_box(inspector, geometries)
    if box is not None:
        for array in box:
            array.flags.writeable = False
    with _BOXES_LOCK:
        _BOXES[key] = box
        while len(_BOXES) > _BOXES_KEPT:
            _BOXES.popitem(last=False)
    return box


def _bounding_box(
    inspector: SceneGraphInspector, geometries: Sequence[GeometryId]
) -> Optional[tuple[np.ndarray, np.ndarray]]:
    corners = []
    for geometry_id in geometries:
        obb = oriented_bounding_box(inspector, geometry_id)
        if obb is None:
            return None
        X_FO = inspector.GetPoseInFrame(geometry_id) @ obb.pose()
        corners.append(
            X_FO.rotation().matrix() @ (BOX_CORNERS * obb.half_width()).T + X_FO.translation()[:, None]
        )
    points = np.concatenate(corners, axis=1)
    low, high = points.min(axis=1), points.max(axis=1)
    return (low + high) / 2, (high - low) / 2
