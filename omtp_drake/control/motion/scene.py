"""The planning scene: what the planner avoids besides the cell's own models.

The collision model (:mod:`omtp_drake.control.motion.collision`) holds the static
cell; this module is the one place that edits what is added to it: extra boxes in
the world (``obstacle_<i>``, e.g. parts lying around, as the caller gives them) and
a part held by the gripper (``held_part``, on the cup body C). Collision reports
name added geometry by these labels (:meth:`PlanningScene.label`).

Notation: ``X_WO`` is an obstacle O's centre pose in world, ``X_CP`` a held part
P's centre pose in the cup body C.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.geometry import Box, GeometryId, Role
from pydrake.math import RigidTransform
from pydrake.multibody.tree import RigidBody
from pydrake.planning import SceneGraphCollisionChecker

from omtp_drake.errors import ConfigError

#: What one obstacle is: its pose in world and its size (edge or x, y, z edges).
Obstacle = tuple[RigidTransform, float | Sequence[float]]

_HELD_GROUP = "held_part"
_OBSTACLE_GROUP = "obstacles"


class PlanningScene:
    """The obstacles and the held part added to ``checker``'s model.

    Args:
        checker: the collision checker of the cell (its robot: one arm and gripper).
        cup: the gripper's cup body C (None: the arm has no gripper).
        robot: the arm's name, for messages.
    """

    def __init__(self, checker: SceneGraphCollisionChecker, cup: RigidBody | None, robot: str) -> None:
        self._checker = checker
        self._cup = cup
        self._robot = robot
        self._obstacle_ids: list[GeometryId] = []
        self._held_ids: list[GeometryId] = []

    @property
    def holds_part(self) -> bool:
        """Whether a held part is in the scene."""
        return bool(self._held_ids)

    def set_obstacles(self, boxes: Sequence[Obstacle]) -> None:
        """Replaces the extra world obstacles by ``boxes``: each ``(X_WO, size)``, the
        box's centre pose in world and its edge (one number) or x, y, z edges (m).

        Collisions with them are reported as ``obstacle_<i>`` (i: index in ``boxes``).
        """
        self._checker.RemoveAllAddedCollisionShapes(_OBSTACLE_GROUP)
        self._obstacle_ids = []
        world = self._checker.plant().world_body()
        for i, (X_WO, size) in enumerate(boxes):
            box = _box(size, f"obstacle {i}")
            before = self.body_geometries(world)
            self._checker.AddCollisionShapeToBody(_OBSTACLE_GROUP, world, box, RigidTransform(X_WO))
            self._obstacle_ids += sorted(
                set(self.body_geometries(world)) - set(before), key=lambda g: g.get_value()
            )

    def set_held_part(self, X_CP: RigidTransform, size: float | Sequence[float]) -> None:
        """A box-shaped part held by the gripper: P's centre at ``X_CP`` in the cup
        body C (``<gripper>_cup``, origin on the cup face, +z out of the tool).

        Replaces any part held before. Collisions with it are reported as ``held_part``.
        The part itself may touch the cup face (same body); everything else is checked.
        """
        if self._cup is None:
            raise ConfigError(f"{self._robot} has no gripper to hold a part")
        self.clear_held_part()
        box = _box(size, "held part")
        before = self.body_geometries(self._cup)
        self._checker.AddCollisionShapeToBody(_HELD_GROUP, self._cup, box, RigidTransform(X_CP))
        self._held_ids = sorted(
            set(self.body_geometries(self._cup)) - set(before), key=lambda g: g.get_value()
        )

    def clear_held_part(self) -> None:
        """The gripper holds nothing."""
        self._checker.RemoveAllAddedCollisionShapes(_HELD_GROUP)
        self._held_ids = []

    def body_geometries(self, body: RigidBody) -> list[GeometryId]:
        """The proximity geometries of ``body``, added boxes included."""
        inspector = self._checker.model_context().GetQueryObject().inspector()
        frame = self._checker.plant().GetBodyFrameIdOrThrow(body.index())
        return list(inspector.GetGeometries(frame, Role.kProximity))

    def label(self, geometry: GeometryId, body: RigidBody) -> str:
        """The name of ``geometry`` (of ``body``) in collision reports: ``obstacle_<i>``,
        ``held_part``, or the body's name."""
        if geometry in self._obstacle_ids:
            return f"obstacle_{self._obstacle_ids.index(geometry)}"
        if geometry in self._held_ids:
            return "held_part"
        return body.name()


def _box(size: float | Sequence[float], what: str) -> Box:
    edges = np.broadcast_to(np.asarray(size, dtype=float), (3,))
    if not np.all(edges > 0):
        raise ConfigError(f"{what}: box size must be one edge or x, y, z edges > 0 m, got {size}")
    return Box(*edges)
