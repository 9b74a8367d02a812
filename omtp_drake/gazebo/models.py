"""The cell's Gazebo models as Gazebo's ROS API (both branches) sees them: names, links, poses and twists.

The models and their names are the course world's
(:func:`omtp_drake.cell.gazebo_models.gazebo_models`, the one home of that naming:
``robot1`` with its gripper, ``bin_1_``, ``workcell_``, ``conveyor_belt``, parts
``object_N``...). A link is ``model::link`` (a part's one link is
``object_N::box_base_link``, as the course's spawner's URDF names it).

:class:`GazeboModels` answers Gazebo's questions on a cell: the models in the
world, an entity's pose and twist (a model, a ``model::link``, or ``world``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity

from omtp_drake.cell.gazebo_models import gazebo_models

if TYPE_CHECKING:
    from pydrake.multibody.tree import Body

    from omtp_drake.script import Cell

#: A part's one link, as the course's spawner's URDF (``createObjectURDF("box", ...)``) names it.
PART_LINK = "box_base_link"
#: The names Gazebo takes for the world frame in a reference frame or relative entity.
WORLD_NAMES = ("", "world", "map", "/map")


class GazeboModels:
    """The cell's models and links under their Gazebo names (see the module doc)."""

    def __init__(self, cell: Cell):
        self.cell = cell
        plant = cell.station.plant
        self._plant = plant
        #: Gazebo model name -> part name, for the parts (a part spawned under another
        #: name by /gazebo/spawn_*_model keeps that name while it is in the world).
        self.part_of: dict[str, str] = {p: p for p in cell.station.parts}
        #: Gazebo model name -> its bodies (the first is the model's frame), in the world's order.
        self._bodies: dict[str, list[Body]] = {}
        for model in gazebo_models(plant, cell.scenario):
            bodies = [plant.get_body(b) for i in model.instances for b in plant.GetBodyIndices(i)]
            if bodies:
                self._bodies[model.name] = bodies

    @property
    def _context(self):
        return self._plant.GetMyContextFromRoot(self.cell.runtime.context)

    @property
    def parts(self) -> set[str]:
        """The Gazebo names of the parts (in the world or not)."""
        return set(self.part_of)

    def names(self) -> list[str]:
        """The models in the world now: the fixed ones, then the parts in the world."""
        in_world = set(self.cell.runtime.parts_in_world())
        return [n for n in self._bodies if n not in self.part_of or self.part_of[n] in in_world]

    def rename_part(self, part: str, name: str) -> None:
        """Part ``part`` is Gazebo's model ``name`` from now on."""
        old = next(n for n, p in self.part_of.items() if p == part)
        self._bodies[name] = self._bodies.pop(old)
        del self.part_of[old]
        self.part_of[name] = part

    def models(self) -> list[tuple[str, Body]]:
        """(name, the body of its frame) of every model in the world."""
        return [(m, self._bodies[m][0]) for m in self.names()]

    def links(self) -> list[tuple[str, Body]]:
        """(``model::link``, its body) of every link of the models in the world."""
        return [(f"{m}::{self._link_name(m, b)}", b) for m in self.names() for b in self._bodies[m]]

    def _link_name(self, model: str, body: Body) -> str:
        if model not in self.part_of:
            return body.name()
        # The spawner plugin's URDF names the link after its object (``<name>_base_link``).
        kind = self.cell.station.pool_kinds.get(self.part_of[model])
        return f"{kind}_base_link" if kind else PART_LINK

    def body(self, entity: str) -> Optional[Body]:
        """The body of a model (its frame) or of a ``model::link`` in the world; None if none."""
        model, _, link = entity.partition("::")
        if model not in self.names():
            return None
        bodies = self._bodies[model]
        if not link:
            return bodies[0]
        return next((b for b in bodies if self._link_name(model, b) == link), None)

    def pose(self, body: Body) -> RigidTransform:
        return self._plant.EvalBodyPoseInWorld(self._context, body)

    def velocity(self, body: Body) -> SpatialVelocity:
        return self._plant.EvalBodySpatialVelocityInWorld(self._context, body)

    def relative(self, body: Body, frame: Optional[Body]) -> tuple[RigidTransform, np.ndarray, np.ndarray]:
        """(pose, linear velocity, angular velocity) of ``body`` in ``frame`` (None: world),
        as Gazebo computes them: the velocity differences expressed in the frame."""
        X_WB, V_WB = self.pose(body), self.velocity(body)
        v, w = V_WB.translational(), V_WB.rotational()
        if frame is None:
            return X_WB, v, w
        X_WF, V_WF = self.pose(frame), self.velocity(frame)
        R_FW = X_WF.rotation().inverse()
        return X_WF.inverse() @ X_WB, R_FW @ (v - V_WF.translational()), R_FW @ (w - V_WF.rotational())
