"""Scenarios: the typed schema of ``diagrams/*.yaml`` and how to load them.

A scenario says which world to build: robots, cameras, bins, parts, plant
settings and the seed. It is the analogue of a Gazebo world plus launch file,
and the one home of the cell's facts that may vary (poses, sizes, rates); the
fixed sizes of the cell's pieces live in their model files (``models/``).

Files are read with Drake's typed YAML loader after a check of every key and
value against the schema, so a misspelt key, a wrong type or a non-finite
number is one clear error naming the file, the key and the valid choices.

A scenario file may start from another one with ``base: <name or path>``: the
base is loaded first and the file's keys are merged into it. Mappings merge
key by key; lists of named items (``robots``, ``cameras``, ``bins``,
``parts``) merge item by item by ``name`` (an item of a new name is appended);
other lists and values replace the base's; ``null`` removes an optional item
(``spawner: null``), and the tag ``!replace`` replaces a list or mapping
wholesale (``robots: !replace [...]`` keeps only the robots listed).

Poses of parts and cameras may be written as ``xyz`` / ``rpy`` lists, or as
``pose`` in Drake's ``schema::Transform`` form where that reads better::

    pose: {translation: [-8.0, -2.2, 1.7], rotation: !Rpy {deg: [0, 90, 0]}}

Example::

    from omtp_drake.scenario import load_scenario
    scenario = load_scenario("omtp_factory")          # a name from diagrams/
    scenario = load_scenario("my_world.yaml")         # or a path
"""

# No `from __future__ import annotations`: Drake's typed YAML loader reads
# the dataclass field types at run time.
import dataclasses
import difflib
import math
import re
import typing
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import numpy as np
import yaml
from pydrake.common.schema import Transform
from pydrake.common.yaml import yaml_load_typed
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import MultibodyPlantConfig

from omtp_drake.assets import UR_MODELS, model_dimensions
from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError, check_rate
from omtp_drake.logical_camera import LogicalCameraConfig
from omtp_drake.parts import SpawnerConfig
from omtp_drake.suction import SuctionConfig

#: Folder of the scenario files shipped with the package.
DIAGRAMS_DIR = Path(__file__).resolve().parent.parent / "diagrams"

#: The cell's floor: a square of this half width (m) about the world origin
#: (the original's 20.1 m plane); nothing may start outside it or below it.
FLOOR_HALF_WIDTH = 10.0
#: The shortest plant step (s): 0.1 ms; shorter ones only make a run crawl.
MIN_TIME_STEP = 1e-4
#: The most parts a pool may hold: every one is a body in the plant, and the build
#: grows faster than linearly (fill_bin's FactoryRuntime: 0.6 s with 12 parts, 2.1 s
#: with 100, 88 s with 500).
MAX_PART_POOL = 100


@dataclass
class RobotConfig:
    """A UR arm on a pedestal, with an optional vacuum gripper on its flange."""

    #: Instance name and frame prefix: ``robot1`` gives ``robot1_base_link``.
    name: str = "robot1"
    #: ``ur10`` or ``ur5`` (classic, from example-robot-data).
    model: str = "ur10"
    #: Pedestal position on the floor (world x, y) and height; the arm's base
    #: sits on top of it.
    xy: list[float] = field(default_factory=lambda: [0.5, 1.8])
    pedestal_height: float = 0.95
    #: Rotation of the arm's base about world z.
    yaw: float = 0.0
    #: Prefix of the course's named poses for this arm (``R1`` -> ``R1Home``).
    pose_prefix: str = "R1"
    #: Joint positions at t = 0: a named pose (``Home`` or ``R1Home``).
    initial_pose: str = "Home"
    #: Name of the vacuum gripper on tool0 (empty: none).
    gripper: str = "vacuum_gripper1"
    #: Symmetric joint position limit (the course limits every joint to pi).
    joint_limit: float = math.pi
    #: Rate (Hz) at which the servo samples the position command and
    #: differentiates it into a desired velocity (a real UR: 125 Hz). Match a
    #: discrete commander's rate (DiffIK runs at 100 Hz) so velocities are smooth.
    command_rate_hz: float = 100.0
    #: Servo gains (per joint, acceleration units): a critically damped 30 rad/s
    #: loop. Peak cup speed over a 1 m/s plan (lecture6_assignment4, fill_bin):
    #: 1.014 at kp 400, 1.008 at 900, 1.013 at 1600; CPU per simulated second
    #: within the run-to-run noise. ``ki > 0`` adds an integral (Drake's
    #: InverseDynamicsController), which gives the simulator continuous state to
    #: integrate: about 20 % of a run's time, for a pole at -ki/kp that hardly acts
    #: within a pick.
    kp: float = 900.0
    kd: float = 60.0
    ki: float = 0.0


#: Names of the cell's fixed models and Drake's own (a robot's pedestal is
#: ``<robot>_pedestal``): no robot, camera, bin or part may take one.
RESERVED_NAMES = (
    "world",
    "floor",
    "conveyor",
    "deletion_wall",
    "break_beam",
    "WorldModelInstance",
    "DefaultModelInstance",
)


@dataclass(frozen=True)
class BinGeometry:
    """The fixed sizes of every bin, read from ``models/bin.urdf.xacro``."""

    #: Half the inner width (m): the inner faces of the walls.
    inner_half_width: float
    #: Height (m) of the top of the bin's floor above its base frame.
    floor_top: float
    #: Height (m) of the rim above the base frame.
    height: float

    @classmethod
    def from_model(cls) -> "BinGeometry":
        d = model_dimensions("bin.urdf.xacro")
        return cls(inner_half_width=d["outer"] / 2 - d["wall"], floor_top=d["floor_top"], height=d["height"])


@dataclass
class BinConfig:
    """An open bin standing on the floor (models/bin.urdf.xacro)."""

    name: str = "bin_1"
    xyz: list[float] = field(default_factory=lambda: [-8.0, -2.2, 0.0])
    yaw: float = 0.0

    @property
    def geometry(self) -> BinGeometry:
        return _BIN_GEOMETRY

    def X_WB(self) -> RigidTransform:
        """The bin's base frame in world (as placed by the scenario)."""
        return RigidTransform(RollPitchYaw(0.0, 0.0, self.yaw), self.xyz)

    def contains(self, p_W, X_WB: Optional[RigidTransform] = None) -> bool:
        """Is the world point ``p_W`` (a part's centre) in the bin: inside the
        inner footprint, above the bin's floor and less than 0.5 m above its rim?
        ``X_WB``: the bin's pose if it is not where the scenario put it."""
        p_B = (X_WB or self.X_WB()).inverse() @ np.asarray(p_W, dtype=float)
        g = _BIN_GEOMETRY
        return bool(
            abs(p_B[0]) < g.inner_half_width
            and abs(p_B[1]) < g.inner_half_width
            and g.floor_top < p_B[2] < g.height + 0.5
        )

    def rim_height(self) -> float:
        """World height of the bin's rim."""
        return self.xyz[2] + _BIN_GEOMETRY.height


_BIN_GEOMETRY = BinGeometry.from_model()


@dataclass
class PartConfig:
    """A part (a uniform cube) placed in the world at t = 0."""

    name: str = "object_1"
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.1])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: The pose as a ``schema::Transform`` instead of ``xyz`` / ``rpy`` (see module doc).
    pose: Optional[Transform] = None
    size: float = 0.2
    mass: float = 0.2


@dataclass
class ConveyorConfig:
    """The conveyor belt (always at the reference pose)."""

    #: Initial power in percent, 0...100 (belt speed = 0.2 m/s x power / 100).
    power: float = 0.0
    #: The course's helper: set the power to 0 when the break beam becomes broken.
    stop_on_beam: bool = False


@dataclass
class TaskConfig:
    """A pick-and-place task: which robot moves how many parts into which bin,
    seen by which cameras; and the planner's tuning.

    Heights and slots follow each part's size, which the planner takes from the
    scenario (``parts`` and ``pool_part_size``). Success: ``parts`` parts in
    ``bin`` and none lost (see omtp_drake.tasks).
    """

    #: How many parts must end in the bin.
    parts: int = 1

    robot: str = "robot2"
    #: The camera that sees the parts to pick, and the one over the bin.
    camera: str = "logical_camera_2"
    bin: str = "bin_1"
    bin_camera: str = ""
    #: Type of the parts to pick (camera ``type``).
    part_type: str = "object"
    #: Heights (m) of the approach above the top face, and of the tip above the
    #: bin's rim during transfer.
    approach_height: float = 0.1
    transfer_clearance: float = 0.05
    #: Tool speed limit (m/s), and the slow speed of the last few cm before contact.
    max_tool_speed: float = 1.0
    descent_speed: float = 0.1
    #: The descent slows down this far (m) above the top face.
    slow_zone: float = 0.02
    #: How far the tip target goes below the top face (m): just enough for contact.
    press_depth: float = 0.003
    attach_timeout: float = 1.0
    detect_timeout: float = 15.0
    #: A part being picked again that no camera has seen for this long (s), or
    #: that lies out of reach, is given up on (recorded "lost" with its position).
    lost_timeout: float = 3.0
    max_attempts: int = 3
    #: DiffIK tracking: position error (m) tolerated, and for how long (s).
    tracking_tolerance: float = 0.03
    tracking_time: float = 0.5
    #: Images older than this (s) count as missing.
    image_timeout: float = 0.5
    update_rate_hz: float = 20.0
    diffik_rate_hz: float = 100.0
    #: Place parts on a grid of slots (fill a bin) instead of all at its centre.
    grid: bool = True
    #: Settle time after release before verifying (the part drops ~2 cm).
    settle_time: float = 0.3

    def validate(self) -> None:
        if not 0 < self.max_tool_speed <= 1.0:
            raise ConfigError(f"task.max_tool_speed must be in (0, 1] m/s, got {self.max_tool_speed}")
        for key in (
            "approach_height",
            "descent_speed",
            "slow_zone",
            "attach_timeout",
            "detect_timeout",
            "lost_timeout",
            "tracking_tolerance",
            "tracking_time",
            "image_timeout",
            "settle_time",
        ):
            if not getattr(self, key) > 0:
                raise ConfigError(f"task.{key} must be > 0, got {getattr(self, key)}")
        for key in ("update_rate_hz", "diffik_rate_hz"):
            check_rate(f"task.{key}", getattr(self, key))
        for key in ("transfer_clearance", "press_depth"):
            if not getattr(self, key) >= 0:
                raise ConfigError(f"task.{key} must be >= 0, got {getattr(self, key)}")
        if self.parts < 1:
            raise ConfigError(f"task.parts must be >= 1, got {self.parts}")
        if self.max_attempts < 1:
            raise ConfigError(f"task.max_attempts must be >= 1, got {self.max_attempts}")


def _default_plant_config() -> MultibodyPlantConfig:
    # 5 ms steps: SAP is built for large steps. CPU per simulated second of a
    # fill_bin run: 362 ms at 2 ms, 204 at 4 ms (integral servo), then 214 -> 178
    # from 4 to 5 ms (stateless servo); every outcome test stays green (no snap at
    # attach, held-part drift, belt speed) and fill_bin succeeds for seeds 0-39,
    # lecture7_conveyor_pick for 0-19. Commands (100 Hz) and cameras (10 Hz) fall
    # on step boundaries. SAP is needed for the
    # run-time constraints and the belt's velocity-controlled actuator; point
    # contact is about 2.4x cheaper than hydroelastic here. Unsampled output
    # ports (poses and contacts computed from the current state when read)
    # spare every Python system a call each step: 10-12 % faster.
    return MultibodyPlantConfig(
        time_step=0.005,
        discrete_contact_approximation="sap",
        contact_model="point",
        use_sampled_output_ports=False,
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

    def part_size(self, name: str) -> float:
        """Edge length (m) of the part ``name``: its own ``parts`` entry, else the pool's."""
        for part in self.parts:
            if part.name == name:
                return part.size
        return self.pool_part_size

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

    def validate(self) -> None:
        """Raises :class:`ConfigError` for values no world can be built from, and
        :class:`UnknownNameError` for a reference to something the scenario lacks."""
        _check_finite("", self)
        names: list[str] = []
        for robot in self.robots:
            if robot.model not in UR_MODELS:
                raise UnknownNameError(f"model of {robot.name}", robot.model, UR_MODELS)
            _check_len(f"robots[{robot.name}].xy", robot.xy, 2)
            check_in_cell(f"robots[{robot.name}].xy", [*robot.xy, 0.0])
            if robot.pedestal_height <= 0:
                raise ConfigError(
                    f"robots[{robot.name}].pedestal_height must be > 0, got {robot.pedestal_height}"
                )
            check_rate(f"robots[{robot.name}].command_rate_hz", robot.command_rate_hz)
            if not 0 < robot.joint_limit <= 2 * math.pi:
                raise ConfigError(
                    f"robots[{robot.name}].joint_limit must be in (0, 2 pi], got {robot.joint_limit}"
                )
            for gain in ("kp", "kd", "ki"):
                if getattr(robot, gain) < 0:
                    raise ConfigError(f"robots[{robot.name}].{gain} must be >= 0, got {getattr(robot, gain)}")
            names += [robot.name, f"{robot.name}_pedestal"] + ([robot.gripper] if robot.gripper else [])
        for camera in self.cameras:
            camera.validate()
            if camera.parent == "world":
                check_in_cell(f"cameras[{camera.name}].xyz", camera.xyz)
            names.append(camera.name)
        for b in self.bins:
            _check_len(f"bins[{b.name}].xyz", b.xyz, 3)
            check_in_cell(f"bins[{b.name}].xyz", b.xyz)
            names.append(b.name)
        for part in self.parts:
            _check_len(f"parts[{part.name}].xyz", part.xyz, 3)
            _check_len(f"parts[{part.name}].rpy", part.rpy, 3)
            check_in_cell(f"parts[{part.name}].xyz", part.xyz)
            if part.size <= 0 or part.mass <= 0:
                raise ConfigError(
                    f"parts[{part.name}] needs size > 0 and mass > 0, got {part.size}, {part.mass}"
                )
            names.append(part.name)
        self.suction.validate()
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
        if self.conveyor is not None:
            if not 0 <= self.conveyor.power <= 100:
                raise ConfigError(f"conveyor.power must be in [0, 100], got {self.conveyor.power}")
            if self.conveyor.stop_on_beam and not self.break_beam:
                raise ConfigError("conveyor.stop_on_beam needs break_beam: true")
        _check_len("gravity", self.gravity, 3)
        self._validate_plant_config()
        if self.task is not None:
            self._validate_task(self.task)
        part_names = {part.name for part in self.parts}
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ConfigError(f"names must be unique in a scenario; repeated: {', '.join(dupes)}")
        pool_like = [n for n in names if n not in part_names and re.fullmatch(r"object_\d+", n)]
        if pool_like:
            raise ConfigError(
                f"name {pool_like[0]!r}: names object_<k> are the part pool's; only parts may take one"
            )
        taken = sorted(set(names) & set(RESERVED_NAMES))
        if taken:
            raise ConfigError(
                f"name {taken[0]!r} is taken by the cell; reserved names: {', '.join(RESERVED_NAMES)}"
            )
        for n in names:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", n):
                raise ConfigError(f"name {n!r} must be letters, digits and '_', starting with a letter")

    def _validate_plant_config(self) -> None:
        config = self.plant_config
        if not MIN_TIME_STEP <= config.time_step <= 0.01:
            raise ConfigError(
                f"plant_config.time_step must be in [{MIN_TIME_STEP:g}, 0.01] s (a discrete plant), "
                f"got {config.time_step}"
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


def _check_len(what: str, values: list[float], n: int) -> None:
    if len(values) != n:
        raise ConfigError(f"{what} needs {n} numbers, got {list(values)}")


def check_in_cell(what: str, xyz: Sequence[float]) -> None:
    """A position of the cell: above the floor and within its 20 x 20 m, or ConfigError."""
    x, y, z = (list(xyz) + [0.0])[:3]
    if max(abs(x), abs(y)) > FLOOR_HALF_WIDTH or z < 0:
        raise ConfigError(
            f"{what} = {list(xyz)} is outside the cell; valid: |x|, |y| <= {FLOOR_HALF_WIDTH:g} m "
            "(the floor) and z >= 0 (above it)"
        )


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


def scenario_names() -> list[str]:
    """Names of the scenarios shipped in ``diagrams/``."""
    return sorted(p.stem for p in DIAGRAMS_DIR.glob("*.yaml"))


def _resolve(name_or_path: str | Path) -> Path:
    text = str(name_or_path)
    if text.endswith((".yaml", ".yml")) or "/" in text or Path(text).is_file():
        path = Path(text)
        if not path.is_file():
            raise ScenarioError(
                f"scenario file {text!r} does not exist; scenario names: {', '.join(scenario_names())}"
            )
        return path
    path = DIAGRAMS_DIR / f"{text}.yaml"
    if not path.is_file():
        raise UnknownNameError("scenario", text, scenario_names(), closest=False)
    return path


@dataclass(frozen=True)
class _Tagged:
    """A YAML value with a tag (``!Rpy {deg: [...]}``), kept for Drake's loader."""

    tag: str
    value: Any


class _Loader(yaml.SafeLoader):
    pass


def _construct_tagged(loader: yaml.SafeLoader, suffix: str, node: yaml.Node) -> _Tagged:
    if isinstance(node, yaml.MappingNode):
        value: Any = loader.construct_mapping(node, deep=True)
    elif isinstance(node, yaml.SequenceNode):
        value = loader.construct_sequence(node, deep=True)
    else:
        value = loader.construct_scalar(node)
    return _Tagged("!" + suffix, value)


_Loader.add_multi_constructor("!", _construct_tagged)


class _Dumper(yaml.SafeDumper):
    pass


def _represent_tagged(dumper: yaml.SafeDumper, data: _Tagged) -> yaml.Node:
    if isinstance(data.value, dict):
        return dumper.represent_mapping(data.tag, data.value)
    if isinstance(data.value, list):
        return dumper.represent_sequence(data.tag, data.value)
    return dumper.represent_scalar(data.tag, str(data.value))


_Dumper.add_representer(_Tagged, _represent_tagged)


def _read_yaml(path: Path) -> dict:
    """The file's mapping; malformed YAML is one line with file, line and column."""
    try:
        raw = yaml.load(path.read_text(), Loader=_Loader)  # noqa: S506 (a SafeLoader)
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
        problem = e.problem or e.context or "malformed YAML"
        raise ScenarioError(f"{where}: {problem}") from None
    except yaml.YAMLError as e:
        raise ScenarioError(f"{path}: malformed YAML ({str(e).splitlines()[0]})") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"{path}: cannot be read ({e})") from None
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        raise ScenarioError(f"{path}: a scenario must be a mapping of keys, got {type(raw).__name__}")
    return raw


#: The lists that merge item by item by ``name`` (see module doc).
_NAMED_LISTS = ("robots", "cameras", "bins", "parts")


def _merge(base: Any, child: Any, key: str = "") -> Any:
    """``child`` merged into ``base`` (see the module doc for the rules)."""
    if isinstance(child, _Tagged) and child.tag == "!replace":
        return child.value
    if isinstance(base, dict) and isinstance(child, dict):
        merged = dict(base)
        for k, v in child.items():
            merged[k] = _merge(base[k], v, k) if k in base else v
        return merged
    if (
        key in _NAMED_LISTS
        and isinstance(base, list)
        and isinstance(child, list)
        and all(isinstance(x, dict) and "name" in x for x in base + child)
    ):
        merged_list = [dict(x) for x in base]
        index = {x["name"]: i for i, x in enumerate(merged_list)}
        for item in child:
            if item["name"] in index:
                i = index[item["name"]]
                merged_list[i] = _merge(merged_list[i], item)
            else:
                index[item["name"]] = len(merged_list)
                merged_list.append(item)
        return merged_list
    return child


def _raw_scenario(path: Path, seen: tuple[Path, ...]) -> tuple[dict, str]:
    """The file's mapping merged into its bases' (and the file's own description
    of ``name``)."""
    if path in seen:
        raise ScenarioError(f"scenario {path.name} includes itself through 'base'")
    raw = _read_yaml(path)
    base = raw.get("base")
    if base:
        if not isinstance(base, str):
            raise ScenarioError(f"{path.name}: base must be a scenario name or path, got {base!r}")
        if "/" in base or base.endswith((".yaml", ".yml")):
            base = str((path.parent / base).resolve())
        base_raw, _ = _raw_scenario(_resolve(base).resolve(), seen + (path,))
        raw = _merge(base_raw, {k: v for k, v in raw.items() if k != "base"})
    return raw, path.stem


def load_scenario(name_or_path: str | Path) -> Scenario:
    """Loads a scenario by name (from ``diagrams/``) or from a YAML file path.

    Raises:
        UnknownNameError: no scenario of that name (the message lists them), or
            a reference to a robot, camera or bin the scenario lacks.
        ScenarioError: missing file, malformed YAML, unknown key, bad type.
        ConfigError: a value no world can be built from.
    """
    path = _resolve(name_or_path).resolve()
    raw, stem = _raw_scenario(path, ())
    raw.pop("base", None)
    return scenario_from_dict(raw, source=path.name, name=stem)


def scenario_from_dict(raw: dict, *, source: str = "scenario", name: str = "") -> Scenario:
    """A validated Scenario from plain data (a scenario file's mapping, bases
    already merged). ``source`` names it in error messages."""
    if not isinstance(raw, dict):
        raise ScenarioError(f"{source}: a scenario must be a mapping of keys, got {type(raw).__name__}")
    _check_schema(raw, Scenario, source, "")
    text = yaml.dump(raw, Dumper=_Dumper, sort_keys=False)
    try:
        scenario = yaml_load_typed(schema=Scenario, data=text, defaults=Scenario())
    except (RuntimeError, AssertionError, TypeError, ValueError) as e:
        # What the schema check above let through (Drake's own checks).
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise ScenarioError(f"{source}: bad value or type: {first}") from None
    if not raw.get("name"):
        scenario.name = name
    scenario.base = ""
    _apply_poses(scenario, raw, source)
    scenario.validate()
    return scenario


def _apply_poses(scenario: Scenario, raw: dict, source: str) -> None:
    """Turns each ``pose`` (schema::Transform) into the item's ``xyz`` / ``rpy``."""
    posed: tuple[tuple[str, Sequence[PartConfig | LogicalCameraConfig]], ...] = (
        ("parts", scenario.parts),
        ("cameras", scenario.cameras),
    )
    for key, items in posed:
        raw_items = raw.get(key) or []
        for item, raw_item in zip(items, raw_items):
            if item.pose is None:
                continue
            both = [k for k in ("xyz", "rpy") if k in raw_item]
            if both:
                raise ScenarioError(
                    f"{source}: {key}[{item.name}] gives both pose and {' and '.join(both)}; give one of them"
                )
            try:
                X = item.pose.GetDeterministicValue()
            except (RuntimeError, ValueError) as e:
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose must be a fixed pose: {str(e).splitlines()[0]}"
                ) from None
            if item.pose.base_frame not in (None, "", "world", getattr(item, "parent", "world")):
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose.base_frame {item.pose.base_frame!r} is not "
                    f"supported; valid: world" + (" or the camera's parent" if key == "cameras" else "")
                )
            item.xyz = [float(v) for v in X.translation()]
            item.rpy = [float(v) for v in RollPitchYaw(X.rotation()).vector()]
            item.pose = None


# ----------------------------------------------------------------------------
# The schema check: every key known, every value of its field's type


def schema_fields(schema: Any) -> dict[str, Any]:
    """Field name -> type of a dataclass or a pydrake config class (of the
    scenario's schema); empty for any other type."""
    if dataclasses.is_dataclass(schema):
        hints = typing.get_type_hints(schema)
        return {f.name: hints[f.name] for f in dataclasses.fields(schema)}
    return {f.name: f.type for f in getattr(schema, "__fields__", ())}


def is_record(schema: Any) -> bool:
    """Is ``schema`` a group of keys (a dataclass or config class, not a pose)?"""
    return (dataclasses.is_dataclass(schema) or hasattr(schema, "__fields__")) and schema is not Transform


def _check_schema(value: Any, schema: Any, source: str, path: str) -> None:
    """Raises ScenarioError for an unknown key or a value of the wrong type at ``path``."""
    where = f"{source}: {path}" if path else source
    origin = typing.get_origin(schema)
    if origin is typing.Union:
        options = [a for a in typing.get_args(schema) if a is not type(None)]
        if value is None:
            return
        schema = options[0] if len(options) == 1 else schema
        if len(options) != 1:
            return  # a variant (Drake checks it)
        origin = typing.get_origin(schema)
    if schema is Transform:
        if not isinstance(value, dict):
            raise ScenarioError(f"{where} must be a pose mapping (translation, rotation), got {value!r}")
        unknown = sorted(set(value) - {"base_frame", "translation", "rotation"})
        if unknown:
            raise ScenarioError(
                _unknown_key_message(where, unknown[0], ["base_frame", "translation", "rotation"])
            )
        _check_pose(value, where)
        return
    if is_record(schema):
        if not isinstance(value, dict):
            raise ScenarioError(
                f"{where} must be a mapping of keys ({', '.join(schema_fields(schema))}), got {value!r}"
            )
        fields = schema_fields(schema)
        for key, item in value.items():
            if key not in fields:
                raise ScenarioError(_unknown_key_message(where, str(key), list(fields)))
            _check_schema(item, fields[key], source, f"{path}.{key}" if path else str(key))
        return
    if origin is list:
        (item_schema,) = typing.get_args(schema)
        if not isinstance(value, list):
            raise ScenarioError(f"{where} must be a list, got {value!r}")
        for i, item in enumerate(value):
            label = item.get("name", i) if isinstance(item, dict) else i
            _check_schema(item, item_schema, source, f"{path}[{label}]")
        return
    expected = {float: "a number", int: "an integer", bool: "true or false", str: "a string"}
    if schema in expected:
        ok = {
            float: isinstance(value, (int, float)) and not isinstance(value, bool),
            int: isinstance(value, int) and not isinstance(value, bool),
            bool: isinstance(value, bool),
            str: isinstance(value, str),
        }[schema]
        if not ok:
            raise ScenarioError(f"{where} must be {expected[schema]}, got {value!r}")


def closest_name(name: str, valid: Sequence[str]) -> Optional[str]:
    """The valid name ``name`` was most likely meant to be: a close spelling, or
    one that holds its letters in order (an abbreviation: ``hfov`` for
    ``horizontal_fov``); None when nothing is close."""
    near = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    if near:
        return near[0]

    def holds(word: str) -> bool:
        letters = iter(word)
        return all(c in letters for c in name)

    abbreviations = sorted((v for v in valid if holds(v)), key=len)
    return abbreviations[0] if abbreviations and len(name) >= 2 else None


_ROTATIONS = "!Rpy {deg: [roll, pitch, yaw]}, !AngleAxis {angle_deg: a, axis: [x, y, z]} or !Identity {}"


def _check_pose(value: dict, where: str) -> None:
    """A fixed pose: translation 3 numbers; rotation one of the fixed forms."""

    def numbers(x: Any, n: int) -> bool:
        return (
            isinstance(x, list)
            and len(x) == n
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in x)
        )

    if "translation" in value and not numbers(value["translation"], 3):
        raise ScenarioError(f"{where}.translation must be 3 numbers, got {value['translation']!r}")
    if "base_frame" in value and not isinstance(value["base_frame"], (str, type(None))):
        raise ScenarioError(f"{where}.base_frame must be a frame name, got {value['base_frame']!r}")
    if "rotation" not in value:
        return
    rotation = value["rotation"]
    forms = {"!Rpy": {"deg": 3}, "!AngleAxis": {"angle_deg": 1, "axis": 3}, "!Identity": {}}
    body = rotation.value if isinstance(rotation, _Tagged) else None
    if (
        not isinstance(rotation, _Tagged)
        or rotation.tag not in forms
        or not isinstance(body, dict)
        or set(body) != set(forms[rotation.tag])
        or not all(numbers(body[k] if n > 1 else [body[k]], n) for k, n in forms[rotation.tag].items())
    ):
        raise ScenarioError(f"{where}.rotation must be {_ROTATIONS}, got {_show(rotation)}")


def _show(value: Any) -> str:
    return f"{value.tag} {value.value!r}" if isinstance(value, _Tagged) else repr(value)


def _unknown_key_message(where: str, key: str, valid: list[str]) -> str:
    near = closest_name(key, valid)
    hint = f" (did you mean {near!r}?)" if near else ""
    return f"{where}: unknown key {key!r}{hint}; valid keys: {', '.join(valid)}"
