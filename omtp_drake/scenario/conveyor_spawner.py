"""The course's conveyor spawner plugin (``omtp_gazebo/conveyor_spawner_node``): its
parameters, read once, and its rules, written once.

Every path that meets the plugin uses this module: a launch file's node
(:mod:`omtp_drake.launch.nodes`), the scenario's spawner (:class:`SpawnerConfig`),
the spawns of the cell (:mod:`omtp_drake.sim.driver`) and of ros-run's spawner node
(:mod:`omtp_drake.ros.gazebo.spawner`).

Parameters (the node's private ``~spawner``, as its ``conveyor_objects.yaml``):
``reference_frame``, ``spawn_period``, ``randomization_seed`` and ``objects``, each
with ``name``, ``mesh_resource``, ``initial_pose`` (``position``, ``orientation`` as
roll, pitch, yaw), ``lateral_placement_variance`` (m), ``yaw_placement_variance``
(degrees) and ``spawn_timing_variance`` (s). As the plugin's XmlRpc reads them, every
key is required and each has its type: an integer where the plugin reads a double
(``spawn_period: 10``) fails its node, and so is refused here (one line naming the
key).

Rules of one spawn (the plugin's ``spawnObject``): the object is one of ``objects``
at random; the initial pose (relative to ``reference_frame``) moves along the
reference frame's **y** by a uniform draw in ``[-lateral, lateral]`` (the plugin's
code, whatever its comment says); its orientation turns about its own z by a uniform
draw in ``[-yaw, yaw]`` (``q *= dq``); the spawn waits a uniform draw in
``[0, timing]`` seconds after the timer's tick. The plugin's timer is a roscpp timer
in a single-threaded spinner: a tick's callback starts at the tick or when the previous
callback returned, whichever is later (:func:`callback_start`). The plugin's model is a
URDF of one link with the mesh as visual and collision, ``<mass value="0.2">`` and
``<inertia ixx=iyy=izz=1>`` at the link's origin (:data:`OBJECT_MASS`,
:data:`OBJECT_INERTIA`).

The draws come from the scenario's seed and the config's ``randomization_seed``
(the plugin's ``srand``) and the spawn's index: the same seeds give the same parts in
the same poses, in any run (:func:`draw`).
"""

# No `from __future__ import annotations`: SpawnObjectConfig is a YAML schema.

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from omtp_drake import assets
from omtp_drake.errors import ConfigError

#: A ``SpawnerConfig`` (:mod:`omtp_drake.scenario.configs` imports this module, so the
#: rules below take it untyped: ``objects`` and ``randomization_seed`` are read).
SpawnerConfig = Any

#: The plugin's object: 0.2 kg and a unit inertia (kg m^2) about its link's origin.
OBJECT_MASS = 0.2
OBJECT_INERTIA = (1.0, 1.0, 1.0)
#: Reference frames Gazebo takes as its world frame (gazebo_ros's SpawnModel).
WORLD_FRAMES = ("", "world", "map", "/map")
#: The plugin's ``robot_namespace`` of every spawn request.
ROBOT_NAMESPACE = "omtp"


@dataclass
class SpawnObjectConfig:
    """One entry of the spawner's ``objects``."""

    #: The object's name (``/spawned_part``'s ``frame_id``).
    name: str = "box"
    #: The mesh as the config names it (``package://...``).
    mesh_resource: str = ""
    #: The mesh file it names ("" when no package of the workspace has it).
    mesh_file: str = ""
    #: Initial pose relative to the spawner's reference frame.
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: Half-ranges of the uniform draws: along the reference frame's y (m), in yaw
    #: about the object's z (rad), and the delay after the timer's tick (s).
    lateral_variance: float = 0.0
    yaw_variance: float = 0.0
    timing_variance: float = 0.0

    def validate(self, where: str) -> None:
        if not self.name:
            raise ConfigError(f"{where}: an object needs a name")
        for key in ("xyz", "rpy"):
            values = getattr(self, key)
            if len(values) != 3 or not all(math.isfinite(v) for v in values):
                raise ConfigError(f"{where}: object {self.name} {key} needs 3 finite numbers, got {values}")
        for key in ("lateral_variance", "yaw_variance", "timing_variance"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value >= 0):
                raise ConfigError(
                    f"{where}: object {self.name} {key} must be a finite number >= 0, got {value}"
                )


@dataclass(frozen=True)
class SpawnDraw:
    """What one spawn drew: which object, its offsets, its delay."""

    kind: int
    lateral: float
    yaw: float
    delay: float


def draw(spawner: SpawnerConfig, seed: int, index: int) -> SpawnDraw:
    """The draws of the ``index``-th spawn (0-based) of ``spawner``, from the
    scenario's ``seed`` and the config's ``randomization_seed``; the order of the
    plugin's ``rand()`` calls: object, lateral, yaw, delay."""
    if len(spawner.objects) == 1 and not _varies(spawner.objects[0]):
        # Nothing to draw: the generator's values would be these (and numpy.random, 0.02 CPU s
        # to import, is not needed to build a cell whose spawner varies nothing).
        return SpawnDraw(kind=0, lateral=0.0, yaw=0.0, delay=0.0)
    words = [seed % 2**32, spawner.randomization_seed % 2**32, 7717, index]
    rng = np.random.default_rng(np.random.SeedSequence(words))
    kind = int(rng.integers(len(spawner.objects)))
    r = rng.uniform(0.0, 1.0, 3)
    obj = spawner.objects[kind]
    return SpawnDraw(
        kind=kind,
        lateral=float(-obj.lateral_variance + 2.0 * r[0] * obj.lateral_variance),
        yaw=float(-obj.yaw_variance + 2.0 * r[1] * obj.yaw_variance),
        delay=float(r[2] * obj.timing_variance),
    )


def _varies(obj: SpawnObjectConfig) -> bool:
    """Whether the object's placement or timing has a variance."""
    return bool(obj.lateral_variance or obj.yaw_variance or obj.timing_variance)


def object_pose(spawner: SpawnerConfig, d: SpawnDraw) -> RigidTransform:
    """``X_RO``: the drawn object's pose in the reference frame R."""
    obj = spawner.objects[d.kind]
    R = RollPitchYaw(obj.rpy).ToRotationMatrix() @ RotationMatrix.MakeZRotation(d.yaw)
    return RigidTransform(R, np.array(obj.xyz, dtype=float) + [0.0, d.lateral, 0.0])


@functools.cache
def object_mesh(path: str) -> tuple[Path, tuple[tuple[float, ...], tuple[float, ...]]]:
    """The mesh file Drake reads for an object's mesh file ``path`` (converted once, cached
    by content: :func:`omtp_drake.assets.drake_mesh`) and its bounds (lo, hi corners of its
    bounding box, in the object's frame, m); ConfigError when the file is missing."""
    src = Path(path)
    if not src.is_file():
        raise ConfigError(f"spawner object mesh {path}: no such file")
    dst = assets.drake_mesh(src, collision=True)
    if dst.suffix.lower() == ".obj":
        return dst, assets.obj_bounds(dst)
    import trimesh  # (a .gltf: its nodes' transforms apply)

    lo, hi = trimesh.load(dst, force="mesh").bounds
    return dst, (tuple(map(float, lo)), tuple(map(float, hi)))


def kind_of(spawner: SpawnerConfig, seed: int, index: int) -> str:
    """The object name of the ``index``-th spawn."""
    return spawner.objects[draw(spawner, seed, index).kind].name


def pool_kinds(spawner: SpawnerConfig, seed: int, pool: list[str]) -> dict[str, str]:
    """The object each pool part is built as: the ``j``-th the ``j``-th spawn's (a part
    parked again is spawned again as an object of its kind); {} without objects."""
    if spawner is None or not spawner.objects:
        return {}
    return {name: kind_of(spawner, seed, j) for j, name in enumerate(pool)}


def callback_start(tick: float, previous_return: float) -> float:
    """When a timer tick's callback starts in a single-threaded spinner."""
    return max(tick, previous_return)


# --- reading the node's parameters -------------------------------------------------


def _get(config: Any, key: str, kind: type, where: str) -> Any:
    """``config[key]`` of the XmlRpc type ``kind`` (a double is no int, an int no double)."""
    if not isinstance(config, dict) or key not in config:
        raise ConfigError(f"{where}: the spawner needs {key!r} (the plugin fails to initialise without it)")
    value = config[key]
    ok = isinstance(value, kind) and not isinstance(value, bool)
    if not ok:
        name = {float: "a double (e.g. 1.0)", int: "an integer", str: "a text", list: "a list"}[kind]
        raise ConfigError(f"{where}: {key} {value!r} must be {name}, as the plugin reads it")
    return value


def _vector(value: Any, key: str, where: str) -> list[float]:
    if not isinstance(value, list) or len(value) != 3:
        raise ConfigError(f"{where}: {key} {value!r} needs 3 doubles")
    for v in value:
        if not isinstance(v, float):
            raise ConfigError(
                f"{where}: {key} {value!r}: {v!r} must be a double (e.g. 1.0), as the plugin reads it"
            )
    return [float(v) for v in value]


def _object(item: Any, where: str, mesh_file: Any) -> dict:
    pose = _get(item, "initial_pose", dict, where)
    name = _get(item, "name", str, where)
    resource = _get(item, "mesh_resource", str, where)
    return {
        "name": name,
        "mesh_resource": resource,
        "mesh_file": mesh_file(resource),
        "xyz": _vector(_get(pose, "position", list, where), "initial_pose.position", where),
        "rpy": _vector(_get(pose, "orientation", list, where), "initial_pose.orientation", where),
        "lateral_variance": _get(item, "lateral_placement_variance", float, where),
        "yaw_variance": math.radians(_get(item, "yaw_placement_variance", float, where)),
        "timing_variance": _get(item, "spawn_timing_variance", float, where),
    }


def spawner_params(config: Any, where: str, mesh_file: Any = lambda uri: "") -> dict:
    """The scenario's ``spawner`` section of the node's ``~spawner`` parameters
    (``mesh_file(uri)``: the file a ``mesh_resource`` names, "" for none);
    ConfigError naming ``where`` and the key, as the plugin's loader refuses."""
    objects = _get(config, "objects", list, where)
    if not objects:
        raise ConfigError(f"{where}: objects is empty (the plugin's spawn draws from it)")
    items = [_object(item, f"{where} objects[{i}]", mesh_file) for i, item in enumerate(objects)]
    first = items[0]
    return {
        "xyz": first["xyz"],
        "yaw": first["rpy"][2],
        "period": _get(config, "spawn_period", float, where),
        "randomization_seed": _get(config, "randomization_seed", int, where),
        "reference_frame": _get(config, "reference_frame", str, where),
        "objects": items,
    }
