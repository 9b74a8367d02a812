"""The course's Gazebo models: the cell's model instances under the names the course's
world gives them.

The course builds its Gazebo world from ``omtp.world`` (the conveyor ``conveyor_belt``,
the ``deletion_wall``, the logical cameras) and the launch files'
``spawn_model -model NAME`` calls (``spawn_static_world_objects.launch``,
``spawn_robots.launch``; parts from ``conveyor_spawner.cpp``). So:

=============================  =====================================================
plant model instance(s)        Gazebo model
=============================  =====================================================
``robotN`` + its gripper       ``robotN`` (the gripper is part of the robot's model)
``robotN_pedestal``            ``robotN_pedestal_``
``bin_N``                      ``bin_N_``
``break_beam``                 ``break_beam_``
``floor``                      ``workcell_`` (the factory hall's mesh)
``conveyor``                   ``conveyor_belt``, nesting ``conveyor_belt_fixed`` and
                               ``conveyor_belt_moving``
a model hung on a link         the model of that link (a student's camera bracket on
(``ModelConfig.parent``)       ``robot1_wrist_3_link`` is part of ``robot1``)
anything else                  its own name (``deletion_wall``, ``logical_camera_1``,
                               ``object_3``...)
=============================  =====================================================

A model's type is ARIAC's ``DetermineModelType`` of its name (:func:`model_type`), its
origin where Gazebo has it: models spawned without a pose (pedestals, break beam,
workcell: their links are placed by joints inside the model) at the world origin (a break
beam the student moved: where its spawn put it, :func:`break_beam_origin`), the
conveyor at its pose in ``omtp.world``, every other model at its first body.

The models are listed in the course world's order: the world file's, then the
spawned ones in the launch files' order, then the parts (and anything else) in the
plant's order. :func:`gazebo_models` is the one place this naming lives.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.tree import ModelInstanceIndex

from omtp_drake.cell.cell_models import X_W_BREAK_BEAM
from omtp_drake.cell.conveyor import X_W_CONVEYOR
from omtp_drake.scenario.configs import pose6

if TYPE_CHECKING:
    from pydrake.multibody.plant import MultibodyPlant

    from omtp_drake.scenario import Scenario

#: The conveyor model's pose in ``omtp.world`` (its origin is the belt's upstream end).
X_W_CONVEYOR_BELT_MODEL = RigidTransform(RollPitchYaw(0.0, 0.0, -1.571), [1.2, 5.0, 0.0])
#: The conveyor model's nested models and their poses in it (its ``model.sdf``).
CONVEYOR_NESTED = (
    ("conveyor_belt_fixed", RigidTransform()),
    ("conveyor_belt_moving", RigidTransform([0.0, 0.0, 0.92])),
)
#: The workcell model's bounding box in the world (lo, hi): its collision mesh
#: (``omtp_support/meshes/workcell/collision/workcell.dae``, turned 90 deg about z by
#: ``workcell.urdf.xacro``) spans the 20 m hall up to 1.12 m high. The plant's floor is
#: a half-space, so this box stands in for the mesh.
WORKCELL_BOX_W = (np.array([-10.0513, -10.0513, 0.0]), np.array([10.0513, 10.3028, 1.1226]))

_WORLD_FILE_FIRST = ("conveyor_belt", "deletion_wall")


@dataclass(frozen=True)
class GazeboModel:
    """One model of the course's Gazebo world.

    Attributes:
        name: its Gazebo name (``robot2``, ``bin_1_``, ``object_3``).
        instances: the plant model instances it is made of.
        X_WM: its origin's pose in the world when fixed there (None: at the first
            body of its first instance).
        nested: its nested models: (name, pose in the model).
        box_W: a fixed world bounding box (lo, hi) standing in for its geometry
            (None: the bounding box of its bodies' geometry).
        own_links: whether it has links of its own. Gazebo's box of a model is its
            own links' (``Model::BoundingBox``), so one with nested models only (the
            conveyor) has an empty box, which Gazebo 9's frustum test (ign-math 4,
            face planes only) never rejects: every logical camera lists it.
    """

    name: str
    instances: tuple[ModelInstanceIndex, ...]
    X_WM: Optional[RigidTransform] = None
    nested: tuple[tuple[str, RigidTransform], ...] = ()
    box_W: Optional[tuple[np.ndarray, np.ndarray]] = None
    own_links: bool = True

    @property
    def type(self) -> str:
        return model_type(self.name)


def model_type(name: str) -> str:
    """ARIAC's ``DetermineModelType``: the name after its last ``|``, without a trailing
    ``_<digits>`` or ``_`` and without a ``_clone`` suffix (``object_3`` -> ``object``,
    ``bin_1_`` -> ``bin_1``, ``robot2`` -> ``robot2``)."""
    name = name.rsplit("|", 1)[-1]
    match = re.fullmatch(r"(.{2,})_\d*", name)
    if match is not None:
        name = match.group(1)
    clone = name.rfind("_clone")
    return name[:clone] if clone >= 0 else name


def _rank(name: str, spawned: list[str]) -> tuple[int, int]:
    if name in _WORLD_FILE_FIRST:
        return 0, _WORLD_FILE_FIRST.index(name)
    if name.startswith("logical_camera"):
        return 1, 0
    if name in spawned:
        return 2, spawned.index(name)
    return 3, 0


def gazebo_models(plant: MultibodyPlant, scenario: Scenario) -> tuple[GazeboModel, ...]:
    """The cell's Gazebo models (see the module doc), in the course world's order."""
    grippers = {r.gripper: r.name for r in scenario.robots if r.gripper}
    bins = {b.name for b in scenario.bins}
    robots = {r.name for r in scenario.robots}
    pedestals = {f"{r}_pedestal" for r in robots}
    #: Links the student hung on a piece's link are that piece's model's in Gazebo.
    hung = {m.name: m.parent for m in scenario.models if m.parent}
    by_name: dict[str, GazeboModel] = {}
    for i in range(2, plant.num_model_instances()):  # 0, 1: world and default
        instance = ModelInstanceIndex(i)
        name = plant.GetModelInstanceName(instance)
        if name in grippers:
            robot = by_name[grippers[name]]
            by_name[robot.name] = GazeboModel(robot.name, (*robot.instances, instance))
        elif name in bins or name in pedestals:
            origin = None if name in bins else RigidTransform()
            by_name[f"{name}_"] = GazeboModel(f"{name}_", (instance,), origin)
        elif hung.get(name) == "workcell" and "workcell_" in by_name:  # (in the hall's link)
            hall = by_name["workcell_"]
            by_name["workcell_"] = dataclasses.replace(hall, instances=(*hall.instances, instance))
        elif name in hung and _owner(plant, by_name, hung[name]) is not None:
            owner = by_name[_owner(plant, by_name, hung[name]) or ""]
            by_name[owner.name] = dataclasses.replace(owner, instances=(*owner.instances, instance))
        elif name == "break_beam":
            by_name["break_beam_"] = GazeboModel("break_beam_", (instance,), break_beam_origin(scenario))
        elif name == "floor":
            by_name["workcell_"] = GazeboModel(
                "workcell_", (instance,), RigidTransform(), box_W=WORKCELL_BOX_W
            )
        elif name == "conveyor":
            # A moved conveyor's model moves with its base frame.
            X_WF = scenario.conveyor.X_WF() if scenario.conveyor is not None else X_W_CONVEYOR
            X_WM = X_WF @ X_W_CONVEYOR.inverse() @ X_W_CONVEYOR_BELT_MODEL
            by_name["conveyor_belt"] = GazeboModel(
                "conveyor_belt", (instance,), X_WM, CONVEYOR_NESTED, own_links=False
            )
        else:
            by_name[name] = GazeboModel(name, (instance,))
    spawned = (
        ["break_beam_"]
        + [f"{b.name}_" for b in scenario.bins]
        + [f"{r.name}_pedestal_" for r in scenario.robots]
        + ["workcell_"]
        + [r.name for r in scenario.robots]
    )
    order = sorted(range(len(by_name)), key=lambda k: _rank(list(by_name)[k], spawned) + (k,))
    models = list(by_name.values())
    return tuple(models[k] for k in order)


def _owner(plant: MultibodyPlant, by_name: dict[str, GazeboModel], frame: str) -> Optional[str]:
    """The Gazebo model (listed so far) of the body of ``frame``."""
    instance = plant.GetFrameByName(frame).body().model_instance()
    return next((name for name, model in by_name.items() if instance in model.instances), None)


def break_beam_origin(scenario: Scenario) -> RigidTransform:
    """``X_WM`` of the break beam's Gazebo model: where ``spawn_model`` put it, the world's
    origin in the course (its URDF places the housing at :data:`X_W_BREAK_BEAM` from there);
    a beam the student moved (``break_beam_pose``, the housing's pose as loaded) moves its
    model's origin with it."""
    if not scenario.break_beam_pose:
        return RigidTransform()
    return pose6(scenario.break_beam_pose) @ X_W_BREAK_BEAM.inverse()


def gazebo_name(models: tuple[GazeboModel, ...], instance: ModelInstanceIndex) -> str:
    """The Gazebo model that plant model instance ``instance`` is part of."""
    for model in models:
        if instance in model.instances:
            return model.name
    raise KeyError(f"model instance {int(instance)} is in no Gazebo model")
