"""Where parts are put: parking slots far from the cell and the spawner's poses.

Drake cannot add bodies to a built plant, so every part that may ever appear
is in the plant from the start: the scenario's placed parts and a pool of
``object_1 ... object_N``. A part out of the world is *parked*: far from the
cell (a row at x = 50 m) with its floating joint locked (no motion, no contact,
no cost in the contact solver). Spawning unlocks the next parked pool part and
puts it at the spawn pose; disposal parks a part again. A part at rest may
fall asleep (its joint locked where it lies). :class:`PartStates` says which
parts are parked, asleep or awake in a Context and makes the edits between
those states; the pool's bookkeeping while the cell runs is
:class:`omtp_drake.sim.pool.PartPool`.
"""

# No `from __future__ import annotations`: SpawnerConfig is a YAML schema.

import functools
import logging
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.geometry import CollisionFilterDeclaration, GeometrySet, Role, SceneGraph, Sphere
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.math import SpatialVelocity
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex, RigidBody
from pydrake.systems.framework import Context

from omtp_drake.errors import SimulationError, UnknownNameError
from omtp_drake.scenario.configs import SpawnerConfig
from omtp_drake.scenario.conveyor_spawner import draw, object_pose

_log = logging.getLogger(__name__)

#: Where parked part k waits (x = PARK_X0 + k * PARK_DX, on a line far from the cell).
PARK_X0, PARK_DX, PARK_Y, PARK_Z = 50.0, 0.5, 50.0, 1.0


def free_body_q_indices(body: RigidBody) -> tuple[tuple[int, int, int, int], tuple[int, int, int]]:
    """The indices in the plant's positions ``q`` of free ``body``'s quaternion (w, x, y,
    z) and of its position (a free body's q: the quaternion, then the position)."""
    k = body.floating_positions_start()
    return (k, k + 1, k + 2, k + 3), (k + 4, k + 5, k + 6)


def parking_pose(slot: int) -> RigidTransform:
    """``X_WP`` of the part parked in ``slot`` (its index among all parts)."""
    return RigidTransform([PARK_X0 + slot * PARK_DX, PARK_Y, PARK_Z])


def spawn_pose(
    spawner: SpawnerConfig,
    seed: int,
    index: int,
    xyz: Optional[list[float]] = None,
    yaw: Optional[float] = None,
    X_WR: Optional[RigidTransform] = None,
) -> RigidTransform:
    """The pose of the ``index``-th spawn: the configured pose plus seeded variance,
    or ``xyz`` / ``yaw`` as given (no variance on what is given). A spawner with the
    course's plugin's ``objects`` draws as the plugin does, in its reference frame
    (``X_WR``, the world by default; :mod:`omtp_drake.scenario.conveyor_spawner`).

    The draw depends only on (seed, index), so runs are reproducible.
    """
    if spawner.objects and xyz is None and yaw is None:
        X_RO = object_pose(spawner, draw(spawner, seed, index))
        return X_RO if X_WR is None else X_WR @ X_RO
    rng = np.random.default_rng((seed, 7919, index))
    dx, dyaw = rng.uniform(-1.0, 1.0, 2)
    p = np.array(xyz if xyz is not None else spawner.xyz, dtype=float)
    if xyz is None:
        p[0] += dx * spawner.lateral_variance
    angle = (yaw if yaw is not None else spawner.yaw) + (dyaw * spawner.yaw_variance if yaw is None else 0.0)
    return RigidTransform(RollPitchYaw(0.0, 0.0, angle), p)


def set_contact_geometry(
    scene_graph: SceneGraph,
    plant: MultibodyPlant,
    root_context: Context,
    geometries: list,
    present: bool,
) -> None:
    """Puts ``geometries`` (the plant's collision geometries) into SceneGraph's
    proximity engine in ``root_context`` (``present``), with the properties they were
    registered with, or takes them out (a parked part: no pose updates, no queries).
    Geometry already where it is asked to be is left alone."""
    context = scene_graph.GetMyMutableContextFromRoot(root_context)
    model = scene_graph.model_inspector()
    now = scene_graph.get_query_output_port().Eval(context).inspector()
    for geometry in geometries:
        if (now.GetProximityProperties(geometry) is not None) == present:
            continue
        if present:
            properties = model.GetProximityProperties(geometry)
            scene_graph.AssignRole(context, plant.get_source_id(), geometry, properties)
        else:
            scene_graph.RemoveRole(context, plant.get_source_id(), geometry, Role.kProximity)


@dataclass(frozen=True)
class CollisionGeometries:
    """The collision geometries of the parts, and of what never moves."""

    #: part -> its collision geometries.
    parts: dict[str, list]
    #: part -> its corner spheres (its points of contact on a flat surface).
    corners: dict[str, list]
    #: Geometries of bodies welded to the world (they never move).
    anchored: list


@dataclass(frozen=True)
class _PartSlots:
    """Each part's free joint, where its position is in q, and its parking slot
    (parking sets the position exactly; nothing else puts a part there)."""

    names: list[str]
    joints: list
    #: Each part's position's indices in q and its parking position.
    slots: list[tuple[tuple[int, int, int], tuple[float, float, float]]]


class PartStates:
    """Which parts are parked, asleep or awake in a Context, and the edits between
    those states (made between advances: they write the plant's and SceneGraph's
    Contexts).

    Each state is a fact of the Context, never restated elsewhere:

    * *parked*: the part's free joint locked at its parking slot, its collision
      geometry out of SceneGraph's proximity engine (out of the world, at no cost);
    * *asleep*: its joint locked anywhere else, its pairs with what never moves
      filtered and its corner spheres out of the proximity engine (see
      :mod:`omtp_drake.cell.rest_clock`);
    * *awake*: its joint free.
    """

    def __init__(self, plant: MultibodyPlant, scene_graph: SceneGraph, parts: dict[str, ModelInstanceIndex]):
        self.plant = plant
        self.scene_graph = scene_graph
        self.parts = dict(parts)

    def park(self, root_context: Context, name: str) -> None:
        """Parks part ``name``: at rest at its parking pose, its joint locked and its
        collision geometry out of SceneGraph's proximity engine.

        A locked joint leaves the contact solver's problem, and geometry without a
        proximity role leaves the geometry queries (whose pose updates otherwise
        touch every parked part's nine geometries at every step): parked parts
        cost nothing. A sleeping part is woken first (its collision filters undone).
        """
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        joint = self._free_joint(name)
        was_parked = self.is_parked(plant_context, name)
        self.wake(root_context, name)
        joint.Unlock(plant_context)
        body = self.plant.GetBodyByName(name, self.parts[name])
        self.plant.SetFreeBodyPose(plant_context, body, parking_pose(list(self.parts).index(name)))
        self.plant.SetFreeBodySpatialVelocity(plant_context, body, SpatialVelocity.Zero())
        joint.Lock(plant_context)
        if not was_parked:
            set_contact_geometry(
                self.scene_graph, self.plant, root_context, self.geometries.parts[name], present=False
            )

    def unpark(self, root_context: Context, name: str, X_WP: RigidTransform) -> None:
        """Frees part ``name`` (parked) and puts it at rest at ``X_WP``, its collision
        geometry back."""
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        if not self.is_parked(plant_context, name):
            raise SimulationError(f"part {name!r} is not parked: it is in the world already")
        geometries = self.geometries.parts[name]
        set_contact_geometry(self.scene_graph, self.plant, root_context, geometries, present=True)
        self._free_joint(name).Unlock(plant_context)
        body = self.plant.GetBodyByName(name, self.parts[name])
        self.plant.SetFreeBodyPose(plant_context, body, X_WP)
        self.plant.SetFreeBodySpatialVelocity(plant_context, body, SpatialVelocity.Zero())

    def is_parked(self, plant_context: Context, name: str) -> bool:
        """Part ``name`` is out of the world: its joint locked at its parking slot."""
        self._free_joint(name)  # UnknownNameError for a name that is no part
        return name in self.parked(plant_context)

    def is_asleep(self, plant_context: Context, name: str) -> bool:
        """Part ``name`` sleeps: in the world, its joint locked (see :mod:`omtp_drake.cell.rest_clock`)."""
        if not self._free_joint(name).is_locked(plant_context):
            return False
        (i, j, k), (x, y, z) = self._part_slots.slots[self._part_slots.names.index(name)]
        q = self.plant.GetPositions(plant_context)
        return not (abs(q[i] - x) < 1e-9 and abs(q[j] - y) < 1e-9 and abs(q[k] - z) < 1e-9)

    def locked(self, plant_context: Context) -> tuple[list[str], list[str]]:
        """(parked, asleep): the parts whose joints are locked, split by where they are,
        in the order of ``parts`` (one read of the plant's positions)."""
        slots = self._part_slots
        parked: list[str] = []
        asleep: list[str] = []
        for name, joint, parked_there in zip(slots.names, slots.joints, self._at_slot(plant_context)):
            if joint.is_locked(plant_context):
                (parked if parked_there else asleep).append(name)
        return parked, asleep

    def parked(self, plant_context: Context) -> list[str]:
        """The parked parts, in the order of ``parts``: ``locked()[0]``, asking only the
        parts at their slots whether they are locked (the pool's and the spawner's
        question, at 20 Hz)."""
        slots = self._part_slots
        return [
            name
            for name, joint, at_slot in zip(slots.names, slots.joints, self._at_slot(plant_context))
            if at_slot and joint.is_locked(plant_context)
        ]

    def any_free(self, plant_context: Context) -> bool:
        """Whether some part's joint is free (awake, held, falling: a part that may move)."""
        return not all(joint.is_locked(plant_context) for joint in self._part_slots.joints)

    def _at_slot(self, plant_context: Context) -> list[bool]:
        """Whether each part (in the order of ``parts``) is at its parking slot (in plain
        floats: a dozen parts cost less than numpy's small-array calls between plant
        steps, bench/README.md)."""
        q = self.plant.GetPositions(plant_context).tolist()
        return [
            abs(q[i] - x) < 1e-9 and abs(q[j] - y) < 1e-9 and abs(q[k] - z) < 1e-9
            for (i, j, k), (x, y, z) in self._part_slots.slots
        ]

    def sleep(self, root_context: Context, name: str) -> None:
        """Part ``name`` (in the world) falls asleep where it is: at rest, its joint
        locked, its contacts with what never moves (bodies welded to the world,
        other sleeping parts) filtered out of SceneGraph's queries, and its corner
        spheres out of the proximity engine: the contact solver and the geometry
        queries drop all of that. Its box keeps its contacts with anything that
        may move, so what touches it is seen (and wakes it) and a part dropped on
        it rests on it (on its own corner spheres)."""
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        self._free_joint(name)
        parked, asleep = self.locked(plant_context)
        if name in parked:
            raise SimulationError(f"part {name!r} is parked (out of the world): it cannot sleep")
        if name in asleep:
            return
        body = self.plant.GetBodyByName(name, self.parts[name])
        self.plant.SetFreeBodySpatialVelocity(plant_context, body, SpatialVelocity.Zero())
        static = list(self.geometries.anchored)
        for other in asleep:
            static += self.geometries.parts[other]
        self._free_joint(name).Lock(plant_context)
        self._filters(root_context).Apply(
            CollisionFilterDeclaration().ExcludeBetween(
                GeometrySet(self.geometries.parts[name]), GeometrySet(static)
            )
        )
        corners = self.geometries.corners[name]
        set_contact_geometry(self.scene_graph, self.plant, root_context, corners, present=False)

    def wake(self, root_context: Context, name: str) -> None:
        """Part ``name`` wakes (joint unlocked, its corner spheres and every contact
        back) if it sleeps; a parked or awake part is left as it is."""
        plant_context = self.plant.GetMyMutableContextFromRoot(root_context)
        if not self.is_asleep(plant_context, name):
            return
        self._free_joint(name).Unlock(plant_context)
        corners = self.geometries.corners[name]
        set_contact_geometry(self.scene_graph, self.plant, root_context, corners, present=True)
        others = list(self.geometries.anchored)
        for other in self.parts:
            if other != name:
                others += self.geometries.parts[other]
        self._filters(root_context).Apply(
            CollisionFilterDeclaration().AllowBetween(
                GeometrySet(self.geometries.parts[name]), GeometrySet(others)
            )
        )

    def _filters(self, root_context: Context):
        return self.scene_graph.collision_filter_manager(
            self.scene_graph.GetMyMutableContextFromRoot(root_context)
        )

    @functools.cached_property
    def geometries(self) -> CollisionGeometries:
        inspector = self.scene_graph.model_inspector()
        part_of = {self.plant.GetBodyByName(n, i).index(): n for n, i in self.parts.items()}
        parts: dict[str, list] = {n: [] for n in self.parts}
        anchored = []
        for geometry in inspector.GetAllGeometryIds(Role.kProximity):
            body = self.plant.GetBodyFromFrameId(inspector.GetFrameId(geometry))
            if body.index() in part_of:
                parts[part_of[body.index()]].append(geometry)
            elif self.plant.IsAnchored(body):
                anchored.append(geometry)
        corners = {n: [g for g in parts[n] if isinstance(inspector.GetShape(g), Sphere)] for n in parts}
        return CollisionGeometries(parts, corners, anchored)

    @functools.cached_property
    def _part_slots(self) -> _PartSlots:
        names, joints, slots = [], [], []
        for k, (name, instance) in enumerate(self.parts.items()):
            (joint_index,) = self.plant.GetJointIndices(instance)
            body = self.plant.GetBodyByName(name, instance)
            names.append(name)
            joints.append(self.plant.get_joint(joint_index))
            x, y, z = parking_pose(k).translation().tolist()
            slots.append((free_body_q_indices(body)[1], (x, y, z)))
        return _PartSlots(names, joints, slots)

    def _free_joint(self, name: str):
        if name not in self.parts:
            raise UnknownNameError("part", name, self.parts)
        return self._part_slots.joints[self._part_slots.names.index(name)]
