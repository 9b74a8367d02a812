"""The scenario schema: :class:`Scenario`, which world to build.

A scenario says which world to build: robots, cameras, bins, parts, plant
settings and the seed. It is the analogue of a Gazebo world plus launch file,
and the one home of the cell's facts that may vary (poses, sizes, rates); the
fixed sizes of the cell's pieces live in their model files (``models/``).
Each piece's config (``configs``, ``camera``, ``suction``) checks its own
values; :meth:`Scenario.validate` checks those and what ties them together
(unique names, cross-references). Files become scenarios in ``loader``.
"""

# No `from __future__ import annotations`: Drake's typed YAML loader reads
# the dataclass field types at run time.
import copy
import dataclasses
import math
import re
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
from pydrake.multibody.plant import MultibodyPlantConfig

from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario.camera import LogicalCameraConfig
from omtp_drake.scenario.configs import (
    RESERVED_NAMES,
    BinConfig,
    ConveyorConfig,
    FrameConfig,
    PartConfig,
    RobotConfig,
    SleepConfig,
    SpawnerConfig,
    TaskConfig,
    check_in_cell,
    check_len,
    check_pose6,
)
from omtp_drake.scenario.conveyor_spawner import draw, object_mesh
from omtp_drake.scenario.faults import FaultConfig
from omtp_drake.scenario.latency import RosLatencyConfig
from omtp_drake.scenario.models import ModelConfig
from omtp_drake.scenario.plugin_names import PluginNames
from omtp_drake.scenario.suction import SuctionConfig

#: The shortest plant step (s): 0.1 ms; shorter ones only make a run crawl.
MIN_TIME_STEP = 1e-4
#: The longest plant step (s) a scenario may ask for. At 16 and 20 ms the task scenarios'
#: outcomes hold, but not the suction's contact nor how parts rest in a bin, so the default
#: stays 10 ms (figures: bench/README.md, "The plant step").
MAX_TIME_STEP = 0.02
#: The most parts a pool may hold: every one is a body in the plant, and the build
#: time grows faster than linearly with them (figures: bench/README.md, "Measured").
MAX_PART_POOL = 100


def _default_plant_config() -> MultibodyPlantConfig:
    # 10 ms steps, as Drake's manipulation station with SAP: the tasks' outcomes and
    # cycle times are the same at 5, 8 and 10 ms. 16 and 20 ms cost 13-32 % less CPU but
    # the pressed cup's contact flickers, parts sleep 15 mm deep in a bin's floor, and at
    # 20 ms 5 cm cubes fail (bench/README.md, "The plant step"). SAP softens near-rigid
    # contacts by (threshold x step)^2: the threshold 0.5 keeps at 10 ms the stiffness
    # a threshold of 1.0 gives at 5 ms (how far the cup presses into a part). The force
    # suction backend sags more at 10 ms (SuctionConfig). Commands (100 Hz), DiffIK,
    # cameras and checks fall on step boundaries. SAP is needed for the run-time constraints and the belt's
    # velocity-controlled actuator; point contact is cheaper than hydroelastic here.
    # Unsampled output ports (poses and contacts computed from the current state when
    # read) spare every Python system a call each step. Figures: bench/README.md, "Measured".
    return MultibodyPlantConfig(
        time_step=0.01,
        discrete_contact_approximation="sap",
        contact_model="point",
        use_sampled_output_ports=False,
        sap_near_rigid_threshold=0.5,
    )


@dataclass
class Scenario:
    """Everything that decides what the factory diagram contains."""

    #: Short name (the file's stem when loaded from a file).
    name: str = ""
    description: str = ""
    #: Another scenario this one starts from (a name or a path); see module doc.
    base: str = ""
    #: Seed of every random thing in the world (camera noise, spawner...).
    seed: int = 0
    plant_config: MultibodyPlantConfig = field(default_factory=_default_plant_config)
    gravity: list[float] = field(default_factory=lambda: [0.0, 0.0, -9.8])
    robots: list[RobotConfig] = field(default_factory=list)
    cameras: list[LogicalCameraConfig] = field(default_factory=list)
    bins: list[BinConfig] = field(default_factory=list)
    #: Parts placed in the world at t = 0.
    parts: list[PartConfig] = field(default_factory=list)
    #: Fixed frames beyond the pieces' own (a student's URDF links; a frame the cell
    #: already has is left as the cell has it).
    frames: list[FrameConfig] = field(default_factory=list)
    #: Parts pre-allocated for spawning (``object_k`` after the placed ones).
    part_pool: int = 0
    #: Edge length (m) and mass (kg) of the pool's parts (uniform cubes).
    pool_part_size: float = 0.2
    pool_part_mass: float = 0.2
    spawner: Optional[SpawnerConfig] = None
    #: The vacuum grippers' behaviour and backend (``weld`` or ``force``).
    suction: SuctionConfig = field(default_factory=SuctionConfig)
    #: A pick-and-place task for ``omtp-drake run``.
    task: Optional[TaskConfig] = None
    conveyor: Optional[ConveyorConfig] = None
    break_beam: bool = False
    deletion_wall: bool = False
    #: Where a student moved the break beam's base / the deletion wall (``x y z roll pitch
    #: yaw`` in world; empty: where the course has them).
    break_beam_pose: list[float] = field(default_factory=list)
    deletion_wall_pose: list[float] = field(default_factory=list)
    #: The scenario's model entry that is the deletion wall as the student's file writes it
    #: ('': the catalogue's box, at ``deletion_wall_pose``); what touches its collisions is disposed of.
    deletion_wall_model: str = ""
    #: ``link::collision`` of that model whose contacts dispose (the one its plugin's contact
    #: sensor watches, as Gazebo's; '': every collision of it).
    deletion_wall_collision: str = ""
    #: The course's plugins' ROS names as the student's ``<plugin>`` parameters set them.
    plugin_names: PluginNames = field(default_factory=PluginNames)
    #: What goes wrong in a run, and when (see :mod:`omtp_drake.scenario.faults`).
    faults: list[FaultConfig] = field(default_factory=list)
    #: Parts at rest fall asleep (leave the contact solver) until touched.
    sleep: SleepConfig = field(default_factory=SleepConfig)
    #: Simulated time a ROS script's calls take under ``ros-run`` (planning, services...).
    ros_latency: RosLatencyConfig = field(default_factory=RosLatencyConfig)
    #: Models from description files (a student's robot, a piece of the course's world).
    models: list[ModelConfig] = field(default_factory=list)

    def part_size(self, name: str) -> float:
        """Size (m) of the part ``name``: a cube's edge (its own ``parts`` entry, else the
        pool's); a pool part built as one of the spawner's mesh objects: the longest edge of
        its mesh's bounding box (:meth:`part_box`)."""
        for part in self.parts:
            if part.name == name:
                return part.size
        mesh = _pool_mesh(self, name)
        if mesh is None:
            return self.pool_part_size
        lo, hi = object_mesh(mesh)[1]
        return float(max(h - l for l, h in zip(lo, hi)))

    def part_box(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """The bounding box of the part ``name`` in its own frame: (centre, half extents),
        m. A cube: centred on its origin, half its edge; a pool part built as one of the
        spawner's mesh objects: its mesh's box, wherever the mesh puts it."""
        mesh = None if any(p.name == name for p in self.parts) else _pool_mesh(self, name)
        if mesh is None:
            return np.zeros(3), np.full(3, self.part_size(name) / 2)
        lo, hi = (np.array(v) for v in object_mesh(mesh)[1])
        return (lo + hi) / 2, (hi - lo) / 2

    def pool_names(self) -> list[str]:
        """The pool's parts in spawn order (:func:`pool_names`)."""
        return pool_names(self)

    def required_task(self) -> TaskConfig:
        """The scenario's task (ConfigError when it has none)."""
        if self.task is None:
            raise ConfigError(f"scenario {self.name!r} has no task to run")
        return self.task

    def robot(self, name: str) -> RobotConfig:
        """The robot called ``name`` (the error lists the robots)."""
        for robot in self.robots:
            if robot.name == name:
                return robot
        raise UnknownNameError("robot", name, [r.name for r in self.robots])

    def bin(self, name: str) -> BinConfig:
        """The bin called ``name`` (the error lists the bins)."""
        for b in self.bins:
            if b.name == name:
                return b
        raise UnknownNameError("bin", name, [b.name for b in self.bins])

    def with_time_step(self, time_step: float) -> "Scenario":
        """This scenario with the plant stepping every ``time_step`` seconds (a copy;
        ConfigError for a step outside the valid range)."""
        config = copy.copy(self.plant_config)
        config.time_step = time_step
        stepped = dataclasses.replace(self, plant_config=config)
        stepped._validate_plant_config()
        return stepped

    def validate(self) -> None:
        """Raises :class:`ConfigError` for values no world can be built from, and
        :class:`UnknownNameError` for a reference to something the scenario lacks."""
        _check_finite("", self)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError(f"seed must be an integer >= 0, got {self.seed!r}")
        names = self._validate_pieces()
        self._validate_pool_and_belt()
        check_len("gravity", self.gravity, 3)
        self._validate_plant_config()
        if self.task is not None:
            self._validate_task(self.task)
        _validate_faults(self)
        self._validate_names(names)

    def _validate_pieces(self) -> list[str]:
        """Each robot, camera, bin and part checks itself (and the gripper settings);
        returns the names they add to the world."""
        names: list[str] = []
        for robot in self.robots:
            robot.validate()
            # (a pedestal of the student's own is a model entry: its name comes with the models)
            pedestal = [] if robot.pedestal_model else [f"{robot.name}_pedestal"]
            names += [robot.name, *pedestal] + ([robot.gripper] if robot.gripper else [])
        for camera in self.cameras:
            camera.validate()
            if camera.parent == "world":
                check_in_cell(f"cameras[{camera.name}].xyz", camera.xyz)
            names.append(camera.name)
        for b in self.bins:
            b.validate()
            names.append(b.name)
        for part in self.parts:
            part.validate()
            names.append(part.name)
        for frame in self.frames:
            frame.validate()
        if len({f.name for f in self.frames}) != len(self.frames):
            raise ConfigError(f"frames: names must be unique, got {[f.name for f in self.frames]}")
        for model in self.models:
            model.validate()
            names.append(model.name)
        self.suction.validate()
        self.plugin_names.validate()
        self.sleep.validate()
        self.ros_latency.validate()
        return names

    def _validate_pool_and_belt(self) -> None:
        """The part pool, the spawner that draws from it and the conveyor."""
        if self.pool_part_size <= 0 or self.pool_part_mass <= 0:
            raise ConfigError(
                f"pool parts need size > 0 and mass > 0, got {self.pool_part_size}, {self.pool_part_mass}"
            )
        if not 0 <= self.part_pool <= MAX_PART_POOL:
            raise ConfigError(f"part_pool must be in [0, {MAX_PART_POOL}], got {self.part_pool}")
        if self.spawner is not None:
            self.spawner.validate()
            check_in_cell("spawner.xyz", self.spawner.xyz)
            if self.part_pool == 0:
                raise ConfigError("a spawner needs parts: set part_pool > 0")
        check_pose6("break_beam_pose", self.break_beam_pose)
        check_pose6("deletion_wall_pose", self.deletion_wall_pose)
        if self.deletion_wall_model and self.deletion_wall_model not in {m.name for m in self.models}:
            raise ConfigError(
                f"deletion_wall_model {self.deletion_wall_model!r} is no model entry; valid: "
                + (", ".join(m.name for m in self.models) or "none (no models)")
            )
        if self.deletion_wall_collision and not self.deletion_wall_model:
            raise ConfigError(
                f"deletion_wall_collision {self.deletion_wall_collision!r} needs deletion_wall_model "
                "(the wall's model entry whose link::collision it names)"
            )
        if self.conveyor is not None:
            self.conveyor.validate()
            if self.conveyor.stop_on_beam and not self.break_beam:
                raise ConfigError("conveyor.stop_on_beam needs break_beam: true")

    def _validate_names(self, names: list[str]) -> None:
        """The world's names are unique, well formed, and leave the pool's and the cell's alone."""
        part_names = {part.name for part in self.parts}
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ConfigError(f"names must be unique in a scenario; repeated: {', '.join(dupes)}")
        pool_like = [n for n in names if n not in part_names and re.fullmatch(r"object_\d+", n)]
        if pool_like:
            raise ConfigError(
                f"name {pool_like[0]!r}: names object_<k> are the part pool's; only parts may take one"
            )
        # (the deletion wall's name is free when the wall is a model entry: the cell builds none)
        taken = sorted(set(names) & set(RESERVED_NAMES) - {self.deletion_wall_model} - {""})
        if taken:
            raise ConfigError(
                f"name {taken[0]!r} is taken by the cell; reserved names: {', '.join(RESERVED_NAMES)}"
            )
        for n in names:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", n):
                raise ConfigError(f"name {n!r} must be letters, digits and '_', starting with a letter")

    def _validate_plant_config(self) -> None:
        config = self.plant_config
        if not MIN_TIME_STEP <= config.time_step <= MAX_TIME_STEP:
            raise ConfigError(
                f"plant_config.time_step must be in [{MIN_TIME_STEP:g}, {MAX_TIME_STEP:g}] s "
                f"(a discrete plant), got {config.time_step}"
            )
        choices = {
            "contact_model": ("point", "hydroelastic", "hydroelastic_with_fallback"),
            "discrete_contact_approximation": ("sap", "lagged", "similar"),
        }
        for key, valid in choices.items():
            if getattr(config, key) not in valid:
                raise UnknownNameError(f"plant_config.{key}", getattr(config, key), valid)

    def _validate_task(self, task: TaskConfig) -> None:
        task.validate()
        robots = {r.name: r for r in self.robots}
        if task.robot not in robots:
            raise UnknownNameError("task.robot", task.robot, robots)
        robot = robots[task.robot]
        if not robot.gripper:
            raise ConfigError(f"task.robot {task.robot!r} has no gripper to pick with")
        cameras = [c.name for c in self.cameras]
        for key in ("camera", "bin_camera"):
            value = getattr(task, key)
            if (value or key == "camera") and value not in cameras:
                raise UnknownNameError(f"task.{key}", value, cameras)
        bins = [b.name for b in self.bins]
        if task.bin not in bins:
            raise UnknownNameError("task.bin", task.bin, bins)


def _validate_faults(scenario: Scenario) -> None:
    """Each fault checks itself; names unique; what it names exists in ``scenario``."""
    seen: set[str] = set()
    grippers = [r.name for r in scenario.robots if r.gripper]
    parts = [p.name for p in scenario.parts] + [
        f"object_{k}" for k in range(1, len(scenario.parts) + scenario.part_pool + 1)
    ]
    known = {
        "robot": [r.name for r in scenario.robots],
        "camera": [c.name for c in scenario.cameras],
        "bin": [b.name for b in scenario.bins],
        "part": parts,
    }
    for fault in scenario.faults:
        fault.validate()
        where = f"faults[{fault.name}]"
        if fault.name in seen:
            raise ConfigError(f"fault names must be unique; repeated: {fault.name}")
        seen.add(fault.name)
        for key, valid in known.items():
            value = getattr(fault, key)
            if value and value not in valid:
                raise UnknownNameError(f"{where}.{key}", value, valid)
        if fault.kind == "vacuum_failure" and fault.robot not in grippers:
            raise UnknownNameError(f"{where}.robot (a robot with a gripper)", fault.robot, grippers)
        if fault.kind == "belt_stop" and scenario.conveyor is None:
            raise ConfigError(f"{where}: belt_stop needs the scenario's conveyor")
        if fault.event == "beam" and not scenario.break_beam:
            raise ConfigError(f"{where}: event beam needs break_beam: true")


def pool_names(scenario: Scenario) -> list[str]:
    """The pool's parts in spawn order: ``object_k`` after the placed parts (a name a
    placed part has is skipped)."""
    placed = {p.name for p in scenario.parts}
    names: list[str] = []
    k = 1
    while len(names) < scenario.part_pool:
        if f"object_{k}" not in placed:
            names.append(f"object_{k}")
        k += 1
    return names


def _pool_mesh(scenario: Scenario, name: str) -> Optional[str]:
    """The mesh file of the spawner's object pool part ``name`` is built as (None: a cube)."""
    spawner = scenario.spawner
    if spawner is None or not any(o.mesh_file for o in spawner.objects):
        return None
    pool = pool_names(scenario)
    if name not in pool:
        return None
    return spawner.objects[draw(spawner, scenario.seed, pool.index(name)).kind].mesh_file or None


def _check_finite(path: str, value: Any) -> None:
    """Every number anywhere in the scenario is finite."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise ConfigError(f"{path or 'value'} = {value} is not a finite number")
        return
    if isinstance(value, (list, tuple, np.ndarray)):
        for i, item in enumerate(value):
            _check_finite(f"{path}[{_item_name(item, i)}]", item)
        return
    if dataclasses.is_dataclass(value):
        for f in dataclasses.fields(value):
            _check_finite(f"{path}.{f.name}" if path else f.name, getattr(value, f.name))
        return
    if isinstance(value, MultibodyPlantConfig):
        for f in MultibodyPlantConfig.__fields__:
            _check_finite(f"{path}.{f.name}", getattr(value, f.name))


def _item_name(item: Any, index: int) -> str:
    return getattr(item, "name", None) or str(index)


# ----------------------------------------------------------------------------
# Loading


# ----------------------------------------------------------------------------
# The schema check: every key known, every value of its field's type
