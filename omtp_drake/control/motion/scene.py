"""The planning scene: what the planner avoids besides the cell's own models.

The collision model (:mod:`omtp_drake.control.motion.collision`) holds the static
cell; this module is the one place that edits what is added to it: extra boxes in
the world (named by the caller, e.g. a part by its name; ``obstacle_<i>`` by
default) and boxes carried by the gripper on the cup body C (a held part,
``held_part`` by default, and objects attached to it). Collision reports name
added geometry by these names (:meth:`PlanningScene.label`).

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

from omtp_drake.cell.body_geometry import body_geometries
from omtp_drake.errors import ConfigError

#: What one obstacle is: its pose in world and its size (edge or x, y, z edges).
Obstacle = tuple[RigidTransform, float | Sequence[float]]
#: What the gripper carries: a box's pose in the cup body, its size, its name.
CupBox = tuple[RigidTransform, float | Sequence[float], str]

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
        #: Added geometry -> the name collision reports give it.
        self._obstacle_labels: dict[GeometryId, str] = {}
        self._held_labels: dict[GeometryId, str] = {}

    @property
    def holds_part(self) -> bool:
        """Whether the gripper carries something (a held part, an attached box)."""
        return bool(self._held_labels)

    def set_obstacles(self, boxes: Sequence[Obstacle], names: Sequence[str] | None = None) -> None:
        """Replaces the extra world obstacles by ``boxes``: each ``(X_WO, size)``, the
        box's centre pose in world and its edge (one number) or x, y, z edges (m).

        Collisions with them are reported by ``names`` (one per box; default
        ``obstacle_<i>``, i: index in ``boxes``).
        """
        labels = [f"obstacle_{i}" for i in range(len(boxes))] if names is None else [str(n) for n in names]
        if len(labels) != len(boxes):
            raise ConfigError(f"set_obstacles: {len(boxes)} boxes but {len(labels)} names")
        self._checker.RemoveAllAddedCollisionShapes(_OBSTACLE_GROUP)
        self._obstacle_labels = {}
        world = self._checker.plant().world_body()
        for label, (X_WO, size) in zip(labels, boxes):
            before = set(self.body_geometries(world))
            self._checker.AddCollisionShapeToBody(
                _OBSTACLE_GROUP, world, _box(size, label), RigidTransform(X_WO)
            )
            self._obstacle_labels.update(dict.fromkeys(set(self.body_geometries(world)) - before, label))

    def set_held_part(
        self, X_CP: RigidTransform, size: float | Sequence[float], name: str = "held_part"
    ) -> None:
        """A box-shaped part held by the gripper: P's centre at ``X_CP`` in the cup
        body C (``<gripper>_cup``, origin on the cup face, +z out of the tool).

        Replaces whatever the gripper carried. Collisions with it are reported as
        ``name``. The part itself may touch the cup face (same body); everything else
        is checked.
        """
        self.set_cup_boxes([(X_CP, size, name)])

    def set_cup_boxes(self, boxes: Sequence[CupBox]) -> None:
        """Replaces what the gripper carries by ``boxes``: each ``(X_CB, size, name)``,
        a box B at ``X_CB`` in the cup body (see :meth:`set_held_part`), reported as ``name``."""
        if self._cup is None:
            raise ConfigError(f"{self._robot} has no gripper to hold a part")
        self.clear_held_part()
        for X_CB, size, name in boxes:
            before = set(self.body_geometries(self._cup))
            self._checker.AddCollisionShapeToBody(
                _HELD_GROUP, self._cup, _box(size, name), RigidTransform(X_CB)
            )
            self._held_labels.update(dict.fromkeys(set(self.body_geometries(self._cup)) - before, name))

    def clear_held_part(self) -> None:
        """The gripper carries nothing."""
        self._checker.RemoveAllAddedCollisionShapes(_HELD_GROUP)
        self._held_labels = {}

    def body_geometries(self, body: RigidBody) -> list[GeometryId]:
        """The proximity geometries of ``body``, added boxes included."""
        inspector = self._checker.model_context().GetQueryObject().inspector()
        return body_geometries(self._checker.plant(), inspector, body.index(), roles=(Role.kProximity,))

    def label(self, geometry: GeometryId, body: RigidBody) -> str:
        """The name of ``geometry`` (of ``body``) in collision reports: an added box's
        name, or the body's name."""
        if geometry in self._obstacle_labels:
            return self._obstacle_labels[geometry]
        return self._held_labels.get(geometry, body.name())


def _box(size: float | Sequence[float], what: str) -> Box:
    edges = np.broadcast_to(np.asarray(size, dtype=float), (3,))
    if not np.all(edges > 0):
        raise ConfigError(f"{what}: box size must be one edge or x, y, z edges > 0 m, got {size}")
    return Box(*edges)
