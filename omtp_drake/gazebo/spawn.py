"""Gazebo's spawn services (``/gazebo/spawn_urdf_model``, ``/gazebo/spawn_sdf_model``; ROS 2's
``spawn_entity``) and ``/gazebo/reset_world``: what a spawn request gets.

The cell spawns the course's parts only: the model the course's conveyor spawner
sends (``createObjectURDF``: a ``<robot>`` with one link whose visual and
collision meshes are ``package://omtp_gazebo/meshes/conveyor_objects/box.stl``, or
the ``mesh_resource`` of one of the scenario's spawner objects), as URDF, or the same
link as an SDF ``<model>``. It becomes the next parked part of the scenario's pool
(one built as that object), named as asked, at ``initial_pose`` in
``reference_frame``. Any other model XML raises one NotSupportedError saying
what is supported. ``spawn_urdf_model`` refuses XML that is no URDF, as Gazebo
does (the call fails: :class:`ServiceCallFailed`).

``reset_world`` puts every part in the world back where it entered the world
(its scenario pose, or its spawn pose), at rest.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.math import SpatialVelocity

from omtp_drake.cell.parts import spawn_pose
from omtp_drake.errors import NotSupportedError, OmtpError
from omtp_drake.scenario import SpawnerConfig, check_in_cell

if TYPE_CHECKING:
    from omtp_drake.gazebo.models import GazeboModels
    from omtp_drake.script import Cell

_log = logging.getLogger("gazebo")


class ServiceCallFailed(OmtpError):
    """A Gazebo service call that fails (the service returns false: rospy's ServiceException;
    the message is Gazebo's)."""


@dataclass(frozen=True)
class Reply:
    """A Gazebo service's ``success`` and ``status_message``."""

    success: bool = False
    status_message: str = ""


#: The course's part mesh, as its spawner's configs name it.
COURSE_PART_MESH = "package://omtp_gazebo/meshes/conveyor_objects/box.stl"


def place_part(cell: Cell, part: str, X_WP: RigidTransform, v: Any = (0, 0, 0), w: Any = (0, 0, 0)) -> None:
    """Part ``part`` (in the world) jumps to ``X_WP`` with velocity ``v``, ``w`` (world)."""
    station, context = cell.station, cell.runtime.context
    station.part_states.wake(context, part)
    plant = station.plant
    plant_context = plant.GetMyMutableContextFromRoot(context)
    body = plant.GetBodyByName(part, station.parts[part])
    plant.SetFreeBodyPose(plant_context, body, X_WP)
    plant.SetFreeBodySpatialVelocity(
        plant_context, body, SpatialVelocity(np.asarray(w, dtype=float), np.asarray(v, dtype=float))
    )


def part_meshes(cell: Cell) -> dict[str, Optional[str]]:
    """mesh URI -> the spawner's object it is (None: the course's box of the built-in
    scenarios), the meshes a spawn service takes."""
    spawner = cell.scenario.spawner
    objects: dict[str, Optional[str]] = {}
    for obj in spawner.objects if spawner is not None else []:
        objects[obj.mesh_resource] = obj.name
    return objects or {COURSE_PART_MESH: None}


def model_mesh(xml: str) -> str:
    """The mesh URI of a model :func:`model_xml_problem` accepted."""
    root = ET.fromstring(xml.strip())
    uris = [m.get("filename", "") for m in root.iter("mesh")] + [
        (u.text or "").strip() for u in root.iter("uri")
    ]
    return next(u for u in uris if u)


def model_xml_problem(xml: str, allowed: Collection[str] = (COURSE_PART_MESH,)) -> Optional[str]:
    """None when ``xml`` is a part (URDF or SDF) of one link whose meshes are one of
    ``allowed``; else what it is instead."""
    try:
        root = ET.fromstring(xml.strip())
    except ET.ParseError as e:
        return f"XML that does not parse ({e})"
    if root.tag == "robot":
        links = root.findall("link")
        meshes = [m.get("filename", "") for m in root.iter("mesh")]
    elif root.tag == "sdf":
        links = root.findall("model/link")
        meshes = [(u.text or "").strip() for m in root.iter("mesh") for u in m.iter("uri")]
    else:
        return f"a <{root.tag}> document"
    shapes = sorted({c.tag for g in root.iter("geometry") for c in g})
    if len(links) != 1 or not meshes or len(set(meshes)) != 1 or meshes[0] not in allowed:
        what = ", ".join(sorted(set(meshes))) or "shapes " + (", ".join(shapes) or "none")
        return f"a <{root.tag}> model with {len(links)} link(s) and meshes {what}"
    return None


class PartSpawner:
    """Gazebo's spawn services and reset_world on ``cell``: ``models`` are its Gazebo models,
    ``reference(name)`` the body of a request's reference entity (None: the world; raises
    KeyError when there is none)."""

    def __init__(self, cell: Cell, models: GazeboModels, reference: Callable[[str], Any]):
        self.cell = cell
        self.models = models
        self.reference = reference
        #: index of a spawn among the pool's spawns -> the pose given (spawns of these services).
        self._given: dict[int, RigidTransform] = {}

    def spawn(self, service: str, name: str, xml: str, X_FP: RigidTransform, reference_frame: str) -> Reply:
        """``service`` (a spawn service's name) spawns model ``name`` of ``xml`` at ``X_FP`` in
        ``reference_frame``."""
        if service.endswith("urdf_model") and "<robot" not in xml:
            raise ServiceCallFailed("SpawnModel: Failure - entity format is invalid.")
        kinds = part_meshes(self.cell)
        problem = model_xml_problem(xml, kinds)
        if problem is not None:
            raise NotSupportedError(
                f"{service}: this cell spawns the course's parts only: a URDF <robot> (or SDF <model>) "
                f"with one link whose meshes are one of {', '.join(kinds)}, as the course's conveyor "
                f"spawner sends; got {problem}"
            )
        kind = kinds[model_mesh(xml)]
        models = self.models
        if name in models.names():
            _log.error("SpawnModel: Failure - model name %s already exist.", name)
            return Reply(False, "SpawnModel: Failure - model already exists.")
        try:
            frame = self.reference(reference_frame)
        except KeyError:
            return Reply(False, reference_missing("SpawnModel", "reference_frame"))
        X_WP = X_FP if frame is None else models.pose(frame) @ X_FP
        check_in_cell(f"{service} initial_pose", X_WP.translation())
        pool = self.cell.runtime.pool
        index = pool.spawn_count
        try:
            part = pool.spawn(self.cell.runtime.context, X_WP, kind)
        except OmtpError as e:
            return Reply(False, f"SpawnModel: Failure - {e}")
        self._given[index] = X_WP
        if part != name:
            models.rename_part(part, name)
        return Reply(True, "SpawnModel: Successfully spawned entity")

    def entry_pose(self, part: str) -> RigidTransform:
        """Where part ``part`` entered the world: its last spawn's pose, or its scenario pose."""
        spawns = [e.part for e in self.cell.runtime.pool.events if e.event == "spawn"]
        index = max((k for k, p in enumerate(spawns) if p == part), default=None)
        if index is None:
            placed = next(p for p in self.cell.scenario.parts if p.name == part)
            return RigidTransform(RollPitchYaw(placed.rpy), placed.xyz)
        if index in self._given:
            return self._given[index]
        # A pool part spawned without a pose came from the scenario's spawner.
        event = [e for e in self.cell.runtime.pool.events if e.event == "spawn"][index]
        if event.pose is not None:
            return event.pose
        spawner = self.cell.scenario.spawner or SpawnerConfig()
        return spawn_pose(spawner, self.cell.scenario.seed, index)

    def reset_world(self) -> None:
        """Every part in the world back where it entered it, at rest."""
        for part in self.cell.runtime.parts_in_world():
            place_part(self.cell, part, self.entry_pose(part))


def reference_missing(service: str, field: str, scoped: str = "link") -> str:
    """Gazebo's status message for a reference entity ``field`` that does not exist."""
    return f"{service}: reference {field} not found, did you forget to scope the {scoped} by model name?"
