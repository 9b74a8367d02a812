"""The course's deletion wall (its object disposal plugin): every part touching the wall (the
collision its contact sensor watches) is disposed of, at the plugin's 5 Hz, as a world edit
of the :class:`~omtp_drake.sim.driver.Driver` (disposing of a part writes the plant's
Context, which no system may do)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.geometry import Box, Role, Sphere
from pydrake.systems.framework import Context

from omtp_drake.cell.parts import free_body_q_indices
from omtp_drake.sim.pool import PartPool

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station

#: The deletion wall checks for contact at 5 Hz (the course's rate).
DISPOSAL_PERIOD = 0.2


class DeletionWall:
    """Disposes of every part touching the deletion wall (5 Hz).

    Touching is geometric (SceneGraph's penetration query between the wall's and
    the parts' collision geometry): the plant's contact results would cost an extra
    contact solve at every check. The query runs only when a part's bounding sphere
    reaches one of the wall's boxes: on a busy belt the query of the whole cell,
    with its many part-belt pairs, is costly and nearly always finds nothing
    (figures: bench/README.md, "Measured")."""

    period = DISPOSAL_PERIOD

    def __init__(self, station: Station, pool: PartPool):
        self._station = station
        self._pool = pool
        plant, inspector = station.plant, station.scene_graph.model_inspector()
        # The catalogue's wall, or the student's wall model as written: the collision its
        # plugin's contact sensor watches (``link::collision``; '': every collision of it).
        own, watched = station.scenario.deletion_wall_model, station.scenario.deletion_wall_collision
        bodies = plant.GetBodyIndices(plant.GetModelInstanceByName(own)) if own else []
        walls = [plant.get_body(b) for b in bodies] or [plant.GetBodyByName("deletion_wall")]
        link, _, collision = watched.partition("::")
        walls = [wall for wall in walls if not watched or wall.name() == link]
        frames = [plant.GetBodyFrameIdOrThrow(wall.index()) for wall in walls]
        self._wall = {
            g
            for frame in frames
            for g in inspector.GetGeometries(frame, Role.kProximity)
            if not watched or inspector.GetName(g).rsplit("::", 1)[-1] == collision
        }
        parts = station.part_states.geometries.parts
        self._part_of = {g: n for n, geometries in parts.items() for g in geometries}
        wall = walls[0]
        one = len(walls) == 1 and plant.IsAnchored(wall)
        self._near = _NearWall.of(station, wall, self._wall) if one else None

    def __call__(self, root_context: Context) -> None:
        plant = self._station.plant
        plant_context = plant.GetMyContextFromRoot(root_context)
        if self._near is not None and not self._near.any(plant.GetPositions(plant_context)):
            return  # no part can touch the wall
        query = plant.get_geometry_query_input_port().Eval(plant_context)
        touching = set()
        for pair in query.ComputePointPairPenetration():
            for wall, other in ((pair.id_A, pair.id_B), (pair.id_B, pair.id_A)):
                if wall in self._wall and other in self._part_of:
                    touching.add(self._part_of[other])
        for name in sorted(touching):
            self._pool.dispose(root_context, name)


@dataclass(frozen=True)
class _NearWall:
    """Whether any part may touch a fixed wall made of boxes: the distance from each
    part's origin to each box against the radius of a sphere about that origin
    holding all of the part's collision geometry (a test that never misses a touch)."""

    #: Each part's position's indices in q.
    index: tuple[tuple[int, int, int], ...]
    #: Each part's bounding radius (m).
    radius: tuple[float, ...]
    #: The wall's boxes: (X_WG's rotation (rows), its translation, half extents).
    boxes: tuple

    @staticmethod
    def of(station: Station, wall, wall_geometries) -> Optional[_NearWall]:
        """The test for ``station``'s parts and the anchored body ``wall``; None when a
        geometry is not a box or sphere (then the query always runs)."""
        plant, inspector = station.plant, station.scene_graph.model_inspector()
        X_WWall = wall.EvalPoseInWorld(plant.CreateDefaultContext())
        boxes = []
        for g in wall_geometries:
            shape = inspector.GetShape(g)
            if not isinstance(shape, Box):
                return None
            X_WG = X_WWall @ inspector.GetPoseInFrame(g)
            boxes.append(
                (
                    X_WG.rotation().matrix().tolist(),
                    X_WG.translation().tolist(),
                    (0.5 * shape.size()).tolist(),
                )
            )
        index, radius = [], []
        for name, instance in station.parts.items():
            body = plant.GetBodyByName(name, instance)
            if not body.is_floating_base_body() or not body.has_quaternion_dofs():
                return None
            index.append(free_body_q_indices(body)[1])
            reach = 0.0
            for g in station.part_states.geometries.parts[name]:
                shape = inspector.GetShape(g)
                if isinstance(shape, Box):
                    size = float(np.linalg.norm(shape.size())) / 2
                elif isinstance(shape, Sphere):
                    size = shape.radius()
                else:
                    return None
                reach = max(reach, float(np.linalg.norm(inspector.GetPoseInFrame(g).translation())) + size)
            radius.append(reach)
        return _NearWall(tuple(index), tuple(radius), tuple(boxes))

    def any(self, q: np.ndarray) -> bool:
        """Whether a part at the positions ``q`` may touch the wall (in plain floats:
        a dozen parts cost less than numpy's small-array calls between plant steps)."""
        qs = q.tolist()
        for R_WG, p_WG, half in self.boxes:
            for (i, j, k), r in zip(self.index, self.radius):
                d = (qs[i] - p_WG[0], qs[j] - p_WG[1], qs[k] - p_WG[2])
                outside = 0.0
                for a in range(3):  # the box's axis a: column a of R_WG
                    e = abs(R_WG[0][a] * d[0] + R_WG[1][a] * d[1] + R_WG[2][a] * d[2]) - half[a]
                    if e > 0.0:
                        outside += e * e
                if outside <= r * r:
                    return True
        return False
