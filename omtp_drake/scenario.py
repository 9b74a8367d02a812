"""Scenarios: the typed schema of ``diagrams/*.yaml`` and how to load them.

A scenario says which world to build: robots, cameras, bins, parts, plant
settings and the seed. It is the analogue of a Gazebo world plus launch file.
Files are read with Drake's typed YAML loader, so an unknown or misspelt key is
an error instead of being silently ignored.

A scenario file may start from another one with ``base: <name or path>``: the
base is loaded first and the file's keys replace the base's (a list replaces the
whole list).

Example::

    from omtp_drake.scenario import load_scenario
    scenario = load_scenario("omtp_factory")          # a name from diagrams/
    scenario = load_scenario("my_world.yaml")         # or a path
"""

# No `from __future__ import annotations`: Drake's typed YAML loader reads
# the dataclass field types at run time.
import dataclasses
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np
import yaml
from pydrake.common.yaml import yaml_load_typed
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import MultibodyPlantConfig

from omtp_drake.assets import UR_MODELS
from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError
from omtp_drake.logical_camera import LogicalCameraConfig
from omtp_drake.parts import SpawnerConfig
from omtp_drake.suction import SuctionConfig

#: Folder of the scenario files shipped with the package.
DIAGRAMS_DIR = Path(__file__).resolve().parent.parent / "diagrams"


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
    #: Inverse-dynamics controller gains (per joint, acceleration units).
    kp: float = 400.0
    kd: float = 40.0
    ki: float = 100.0


@dataclass
class BinConfig:
    """An open bin standing on the floor (models/bin.urdf.xacro)."""

    #: Geometry of every bin (reference: inner walls at +/-0.19, floor top at
    #: about 0.12, 0.475 high).
    INNER_HALF_WIDTH = 0.19
    FLOOR_TOP = 0.12
    HEIGHT = 0.475

    name: str = "bin_1"
    xyz: list[float] = field(default_factory=lambda: [-8.0, -2.2, 0.0])
    yaw: float = 0.0

    def X_WB(self) -> RigidTransform:
        """The bin's base frame in world."""
        return RigidTransform(RollPitchYaw(0.0, 0.0, self.yaw), self.xyz)

    def contains(self, p_W) -> bool:
        """Is the world point ``p_W`` inside the bin (within its walls, below its rim)?"""
        p_B = self.X_WB().inverse() @ np.asarray(p_W, dtype=float)
        half = self.INNER_HALF_WIDTH
        return bool(abs(p_B[0]) < half and abs(p_B[1]) < half and p_B[2] < self.HEIGHT)

    def rim_height(self) -> float:
        """World height of the bin's rim."""
        return self.xyz[2] + self.HEIGHT


@dataclass
class PartConfig:
    """A part (a uniform cube) placed in the world at t = 0."""

    name: str = "object_1"
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.1])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
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

    Success: ``parts`` parts in ``bin`` and none lost (see omtp_drake.tasks).
    """

    #: How many parts must end in the bin.
    parts: int = 1

    robot: str = "robot2"
    #: The camera that sees the parts to pick, and the one over the bin.
    camera: str = "logical_camera_2"
    bin: str = "bin_1"
    bin_camera: str = ""
    #: Type of the parts to pick (camera ``type``) and their edge length.
    part_type: str = "object"
    part_size: float = 0.2
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
        for key in ("part_size", "approach_height", "descent_speed", "slow_zone", "attach_timeout",
                    "detect_timeout", "tracking_tolerance", "tracking_time", "image_timeout",
                    "update_rate_hz", "diffik_rate_hz", "settle_time"):
            if getattr(self, key) <= 0:
                raise ConfigError(f"task.{key} must be > 0, got {getattr(self, key)}")
        if self.parts < 1:
            raise ConfigError(f"task.parts must be >= 1, got {self.parts}")
        if self.max_attempts < 1:
            raise ConfigError(f"task.max_attempts must be >= 1, got {self.max_attempts}")


def _default_plant_config() -> MultibodyPlantConfig:
    # 2 ms steps: 1 ms costs twice as much for no visible difference in the
    # course's motions (see bench/bench_factory.py). SAP is needed for the
    # run-time constraints and the belt's velocity-controlled actuator; point
    # contact is about 2.4x cheaper than hydroelastic here. Unsampled output
    # ports (poses and contacts computed from the current state when read)
    # spare every Python system a call each step: 10-12 % faster.
    return MultibodyPlantConfig(
        time_step=0.002,
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

    def validate(self) -> None:
        """Raises :class:`ConfigError` for values no world can be built from."""
        names: list[str] = []
        for robot in self.robots:
            if robot.model not in UR_MODELS:
                raise UnknownNameError(f"model of {robot.name}", robot.model, UR_MODELS)
            _check_len(f"robots[{robot.name}].xy", robot.xy, 2)
            if robot.pedestal_height <= 0:
                raise ConfigError(
                    f"robots[{robot.name}].pedestal_height must be > 0, got {robot.pedestal_height}")
            if robot.command_rate_hz <= 0:
                raise ConfigError(
                    f"robots[{robot.name}].command_rate_hz must be > 0, got {robot.command_rate_hz}")
            if not 0 < robot.joint_limit <= 2 * math.pi:
                raise ConfigError(
                    f"robots[{robot.name}].joint_limit must be in (0, 2 pi], got {robot.joint_limit}")
            names += [robot.name] + ([robot.gripper] if robot.gripper else [])
        for camera in self.cameras:
            camera.validate()
            names.append(camera.name)
        for b in self.bins:
            _check_len(f"bins[{b.name}].xyz", b.xyz, 3)
            names.append(b.name)
        for part in self.parts:
            _check_len(f"parts[{part.name}].xyz", part.xyz, 3)
            _check_len(f"parts[{part.name}].rpy", part.rpy, 3)
            if part.size <= 0 or part.mass <= 0:
                raise ConfigError(
                    f"parts[{part.name}] needs size > 0 and mass > 0, got {part.size}, {part.mass}")
            names.append(part.name)
        self.suction.validate()
        if self.pool_part_size <= 0 or self.pool_part_mass <= 0:
            raise ConfigError(f"pool parts need size > 0 and mass > 0, got "
                              f"{self.pool_part_size}, {self.pool_part_mass}")
        if self.task is not None:
            self.task.validate()
            robots = [r.name for r in self.robots]
            if self.task.robot not in robots:
                raise UnknownNameError("task robot", self.task.robot, robots)
        if self.part_pool < 0:
            raise ConfigError(f"part_pool must be >= 0, got {self.part_pool}")
        if self.spawner is not None:
            self.spawner.validate()
            if self.part_pool == 0:
                raise ConfigError("a spawner needs parts: set part_pool > 0")
        if self.conveyor is not None and not 0 <= self.conveyor.power <= 100:
            raise ConfigError(f"conveyor.power must be in [0, 100], got {self.conveyor.power}")
        _check_len("gravity", self.gravity, 3)
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ConfigError(f"names must be unique in a scenario; repeated: {', '.join(dupes)}")
        for n in names:
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", n):
                raise ConfigError(f"name {n!r} must be letters, digits and '_', starting with a letter")


def _check_len(what: str, values: list[float], n: int) -> None:
    if len(values) != n:
        raise ConfigError(f"{what} needs {n} numbers, got {list(values)}")


def scenario_names() -> list[str]:
    """Names of the scenarios shipped in ``diagrams/``."""
    return sorted(p.stem for p in DIAGRAMS_DIR.glob("*.yaml"))


def _resolve(name_or_path: str | Path) -> Path:
    text = str(name_or_path)
    if text.endswith((".yaml", ".yml")) or "/" in text or Path(text).is_file():
        path = Path(text)
        if not path.is_file():
            raise ScenarioError(
                f"scenario file {text!r} does not exist; scenario names: {', '.join(scenario_names())}")
        return path
    path = DIAGRAMS_DIR / f"{text}.yaml"
    if not path.is_file():
        raise UnknownNameError("scenario", text, scenario_names(), closest=False)
    return path


def load_scenario(name_or_path: str | Path, *, _seen: tuple[Path, ...] = ()) -> Scenario:
    """Loads a scenario by name (from ``diagrams/``) or from a YAML file path.

    Raises:
        UnknownNameError: no scenario of that name (the message lists them).
        ScenarioError: missing file, malformed YAML, unknown key, bad type.
        ConfigError: a value no world can be built from.
    """
    path = _resolve(name_or_path).resolve()
    if path in _seen:
        raise ScenarioError(f"scenario {path.name} includes itself through 'base'")
    try:
        raw = yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as e:
        raise ScenarioError(f"scenario {str(path)!r} is not valid YAML: {e}") from e
    if not isinstance(raw, dict):
        raise ScenarioError(f"scenario {str(path)!r} must be a mapping of keys, got {type(raw).__name__}")
    valid = [f.name for f in dataclasses.fields(Scenario)]
    unknown = sorted(set(raw) - set(valid))
    if unknown:
        raise ScenarioError(
            f"scenario {path.name}: unknown key(s) {', '.join(unknown)}; valid keys: {', '.join(valid)}")
    defaults = Scenario()
    if raw.get("base"):
        base = str(raw["base"])
        if "/" in base or base.endswith((".yaml", ".yml")):
            base = str((path.parent / base).resolve())
        defaults = load_scenario(base, _seen=_seen + (path,))
    try:
        scenario = yaml_load_typed(schema=Scenario, filename=str(path), defaults=defaults)
    except (RuntimeError, AssertionError, TypeError, ValueError) as e:
        # Drake's loader reports a wrong type as a bare assertion of the value.
        raise ScenarioError(f"scenario {path.name}: bad value or type near {e}") from e
    scenario.name = path.stem if not raw.get("name") else scenario.name
    scenario.base = ""
    scenario.validate()
    return scenario
