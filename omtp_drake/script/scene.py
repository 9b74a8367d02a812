"""MoveIt's planning scene of a cell: what the arms' plans and moves avoid.

The scene is the static cell and the other arms (always), the part a gripper
holds (always, it moves with the cup), and the boxes a script adds by name
(``add_box``, or ``add_part`` for a loose part where it lies now). Loose parts
are not in it unless added, as in the course's MoveIt: a goal that puts the cup
on or into a part plans; the part is then pressed and pushed by physics and
suction attaches on contact. ``attach_box`` fixes a box to an arm's gripper
(it moves with the cup); ``detach`` puts it back into the world where it is.

Example::

    scene = cell.planning_scene
    scene.add_box("fence", RigidTransform([-8.0, -1.0, 0.5]), [1.0, 0.05, 1.0])
    scene.add_part("object_1")          # this part is an obstacle from now on
    scene.remove("fence")
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell.poses import PoseStamped
from omtp_drake.errors import ConfigError, StateError, UnknownNameError

if TYPE_CHECKING:
    from omtp_drake.sim.runtime import FactoryRuntime
    from omtp_drake.sim.tf import TfBuffer


@dataclass(frozen=True)
class SceneBox:
    """A box of the scene: ``X`` is its centre's pose in world (``robot`` empty) or in
    the cup body of ``robot``'s gripper (attached); ``size`` its x, y, z edges (m)."""

    name: str
    X: RigidTransform
    size: tuple[float, float, float]
    robot: str = ""


def world_pose(tf: TfBuffer, pose: RigidTransform | PoseStamped) -> RigidTransform:
    """A pose in world: a RigidTransform is one already; a PoseStamped is transformed
    with ``tf`` at its time."""
    if isinstance(pose, PoseStamped):
        return tf.transform_pose(pose, "world").pose
    if isinstance(pose, RigidTransform):
        return pose
    raise ConfigError(f"a pose is a RigidTransform (world) or a PoseStamped, got {type(pose).__name__}")


def _size(size: float | Sequence[float], what: str) -> tuple[float, float, float]:
    values = np.atleast_1d(np.asarray(size, dtype=float)).ravel()
    if values.shape == (1,):
        values = np.repeat(values, 3)
    if values.shape != (3,) or not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise ConfigError(f"{what}: size must be one edge or x, y, z edges, finite and > 0 m, got {size!r}")
    return (float(values[0]), float(values[1]), float(values[2]))


class CellPlanningScene:
    """The planning scene of a running cell (get it as ``cell.planning_scene``)."""

    def __init__(self, runtime: FactoryRuntime, tf: TfBuffer):
        self._runtime = runtime
        self._tf = tf
        self._boxes: dict[str, SceneBox] = {}

    def add_box(self, name: str, pose: RigidTransform | PoseStamped, size: float | Sequence[float]) -> None:
        """Adds (or moves) the box ``name``: its centre at ``pose`` (world, or a
        PoseStamped in any tf frame), ``size`` one edge or x, y, z edges (m)."""
        name = self._check_name(name)
        self._boxes[name] = SceneBox(name, world_pose(self._tf, pose), _size(size, f"box {name!r}"))

    def add_part(self, part: str) -> None:
        """Loose part ``part`` as an obstacle, where it lies now (named by its name)."""
        self.add_box(part, self._runtime.part_pose(part), self._runtime.scenario.part_size(part))

    def remove(self, name: Optional[str] = None) -> None:
        """Removes world box ``name`` (None: every world box)."""
        world = [n for n, b in self._boxes.items() if not b.robot]
        if name is None:
            for n in world:
                del self._boxes[n]
        elif name in world:
            del self._boxes[name]
        else:
            raise UnknownNameError("planning-scene object", name, world)

    def attach_box(
        self, robot: str, name: str, pose: Optional[RigidTransform | PoseStamped] = None, size=None
    ) -> None:
        """Fixes box ``name`` to ``robot``'s gripper: a world box of that name (moved
        from the world), or a new one at ``pose`` (world; default: the cup face) of ``size``."""
        cup = self._cup(robot)
        name = str(name)
        if pose is None and size is None and name in self._boxes and not self._boxes[name].robot:
            X_WO, dims = self._boxes[name].X, self._boxes[name].size
        else:
            if size is None:
                raise ConfigError(f"attach_box {name!r}: give its size (no world object of that name)")
            X_WO = cup if pose is None else world_pose(self._tf, pose)
            dims = _size(size, f"box {name!r}")
        self._boxes[self._check_name(name, allow=name)] = SceneBox(
            name, cup.InvertAndCompose(X_WO), dims, robot
        )

    def detach(self, robot: Optional[str] = None, name: Optional[str] = None) -> None:
        """Puts attached boxes (of ``robot``, named ``name``; None: any) back into the
        world where they are now."""
        attached = [b for b in self._boxes.values() if b.robot and robot in (None, b.robot)]
        if name is not None:
            attached = [b for b in attached if b.name == name]
            if not attached:
                raise UnknownNameError(
                    "attached object", name, [b.name for b in self._boxes.values() if b.robot]
                )
        for b in attached:
            self._boxes[b.name] = SceneBox(b.name, self._cup(b.robot) @ b.X, b.size)

    def names(self) -> list[str]:
        """The world boxes' names (sorted)."""
        return sorted(n for n, b in self._boxes.items() if not b.robot)

    def objects(self) -> dict[str, SceneBox]:
        """World boxes by name."""
        return {n: b for n, b in sorted(self._boxes.items()) if not b.robot}

    def attached(self, robot: Optional[str] = None) -> dict[str, SceneBox]:
        """Attached boxes by name (of ``robot``; None: any)."""
        return {n: b for n, b in sorted(self._boxes.items()) if b.robot and robot in (None, b.robot)}

    def _cup(self, robot: str) -> RigidTransform:
        """``X_WC``: where ``robot``'s cup body is now (the error lists the robots with grippers)."""
        station = self._runtime.station
        gripper = station.arm(robot).config.gripper
        if not gripper:
            raise UnknownNameError("robot with a gripper", robot, list(station.grippers))
        plant = station.plant
        context = plant.GetMyContextFromRoot(self._runtime.context)
        return plant.GetBodyByName(f"{gripper}_cup").EvalPoseInWorld(context)

    def _check_name(self, name: str, allow: str = "") -> str:
        name = str(name)
        if not name:
            raise ConfigError("a planning-scene object needs a name")
        held = self._boxes.get(name)
        if held is not None and held.robot and name != allow:
            raise StateError(f"{name!r} is attached to {held.robot}; detach it first")
        return name
