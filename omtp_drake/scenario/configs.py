"""The scenario's pieces: robots, bins, parts, the belt, the spawner and the task.

Each is a dataclass of the YAML schema (Drake's typed loader reads the field
types at run time) that checks its own values in ``validate()``.
"""

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.common.schema import Transform
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.assets import UR_MODELS, model_dimensions
from omtp_drake.errors import MAX_RATE_HZ, ConfigError, UnknownNameError, check_positive, check_rate
from omtp_drake.scenario.arm_dynamics import check_arm_dynamics
from omtp_drake.scenario.conveyor_spawner import SpawnObjectConfig

#: The cell's floor: a square of this half width (m) about the world origin
#: (the original's 20.1 m plane); nothing may start outside it or below it.
FLOOR_HALF_WIDTH = 10.0


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
    #: The scenario's model entry that is the pedestal as the student's file writes it
    #: ('': the catalogue's box, ``pedestal_height`` high, at ``xy``).
    pedestal_model: str = ""
    #: Rotation of the arm's base about world z.
    yaw: float = 0.0
    #: Prefix of the course's named poses for this arm (``R1`` -> ``R1Home``).
    pose_prefix: str = "R1"
    #: Joint positions at t = 0: a named pose (``Home`` or ``R1Home``).
    initial_pose: str = "Home"
    #: Name of the vacuum gripper on tool0 (empty: none).
    gripper: str = "vacuum_gripper1"
    #: Whether the gripper has its collisions; False where its file gives its links none:
    #: then nothing touches its cup, and its plugin (which grasps on contacts of the cup
    #: link's collisions) grasps nothing, as in Gazebo.
    gripper_collision: bool = True
    #: Symmetric joint position limit (the course limits every joint to pi).
    joint_limit: float = math.pi
    #: Each joint's own symmetric limit (pan, lift, elbow, wrist 1, 2, 3), where the arm's
    #: file gives them apart (ur_description's unlimited arm: 2 pi, the elbow pi); empty:
    #: ``joint_limit`` for every joint.
    joint_limits: list[float] = field(default_factory=list)
    #: Each joint's velocity limit (rad/s) and effort limit (N m), pan ... wrist 3, as the
    #: arm's file writes them; empty: ``model``'s (ur_description's). The velocities bound
    #: DiffIK, the planners' timing and MoveIt's (where no joint_limits.yaml says otherwise);
    #: the efforts bound the arm's actuators in the plant, as Gazebo's joint limits do.
    velocity_limits: list[float] = field(default_factory=list)
    effort_limits: list[float] = field(default_factory=list)
    #: A link's inertial as the arm's file writes it, where it is not the model's: link
    #: (``ARM_LINKS``) -> [mass (kg), x, y, z of its centre of mass (m), ixx, iyy, izz, ixy,
    #: ixz, iyz (kg m^2) about it], all in the link's frame (``scenario.arm_dynamics``). A link
    #: not listed: the model's.
    inertials: dict[str, list[float]] = field(default_factory=dict)
    #: ``<link>/visual`` or ``<link>/collision`` where the arm's file replaced the model's
    #: geometry: the cell's arm drops its own there (theirs is the ``<robot>_<link>_own`` model).
    own_geometry: list[str] = field(default_factory=list)
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

    def limits(self) -> np.ndarray:
        """Each joint's symmetric position limit (rad): ``joint_limits``, else ``joint_limit``."""
        return np.array(self.joint_limits, dtype=float) if self.joint_limits else np.full(6, self.joint_limit)

    def validate(self) -> None:
        """Raises :class:`ConfigError` (or :class:`UnknownNameError` for the model)
        naming the field, its value and the valid range."""
        where = f"robots[{self.name}]"
        if self.model not in UR_MODELS:
            raise UnknownNameError(f"model of {self.name}", self.model, UR_MODELS)
        check_len(f"{where}.xy", self.xy, 2)
        check_in_cell(f"{where}.xy", [*self.xy, 0.0])
        if self.pedestal_height <= 0:
            raise ConfigError(f"{where}.pedestal_height must be > 0, got {self.pedestal_height}")
        check_rate(f"{where}.command_rate_hz", self.command_rate_hz)
        if not 0 < self.joint_limit <= 2 * math.pi:
            raise ConfigError(f"{where}.joint_limit must be in (0, 2 pi], got {self.joint_limit}")
        if self.joint_limits and (
            len(self.joint_limits) != 6 or not all(0 < v <= 2 * math.pi for v in self.joint_limits)
        ):
            raise ConfigError(
                f"{where}.joint_limits must be 6 limits in (0, 2 pi] (or empty), got {self.joint_limits}"
            )
        check_arm_dynamics(where, self.velocity_limits, self.effort_limits, self.inertials, self.own_geometry)
        for gain in ("kp", "kd", "ki"):
            if getattr(self, gain) < 0:
                raise ConfigError(f"{where}.{gain} must be >= 0, got {getattr(self, gain)}")


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
    """A bin's inside, in its base frame: the catalogue's (``models/bin.urdf.xacro``,
    square) or a student's bin's (its walls)."""

    #: Half the inner length (m) along the bin's x: the inner faces of its walls across x.
    inner_half_x: float
    #: Half the inner length (m) along the bin's y.
    inner_half_y: float
    #: Height (m) of the top of the bin's floor above its base frame.
    floor_top: float
    #: Height (m) of the rim above the base frame.
    height: float

    @property
    def inner_half_width(self) -> float:
        """The narrower half inner length (m): room for a part whichever way it turns."""
        return min(self.inner_half_x, self.inner_half_y)

    @classmethod
    def from_model(cls) -> "BinGeometry":
        d = model_dimensions("bin.urdf.xacro")
        half = d["outer"] / 2 - d["wall"]
        return cls(inner_half_x=half, inner_half_y=half, floor_top=d["floor_top"], height=d["height"])


@dataclass
class BinConfig:
    """An open bin standing on the floor (models/bin.urdf.xacro)."""

    name: str = "bin_1"
    xyz: list[float] = field(default_factory=lambda: [-8.0, -2.2, 0.0])
    yaw: float = 0.0
    #: The scenario's model entry that is this bin as the student's file writes it ('':
    #: the catalogue's bin, models/bin.urdf.xacro); its ``<name>_base_link`` stands here.
    model: str = ""
    #: That bin's inner half lengths along its x and y, floor top and rim height (m), from
    #: its walls.
    walls: list[float] = field(default_factory=list)

    @property
    def geometry(self) -> BinGeometry:
        if self.walls:
            half_x, half_y, floor_top, height = self.walls
            return BinGeometry(inner_half_x=half_x, inner_half_y=half_y, floor_top=floor_top, height=height)
        return _BIN_GEOMETRY

    def X_WB(self) -> RigidTransform:
        """The bin's base frame in world (as placed by the scenario)."""
        return RigidTransform(RollPitchYaw(0.0, 0.0, self.yaw), self.xyz)

    def contains(self, p_W, X_WB: Optional[RigidTransform] = None) -> bool:
        """Is the world point ``p_W`` (a part's centre) in the bin: inside the
        inner rectangle (in the bin's frame: its yaw turns it), above the bin's floor and
        less than 0.5 m above its rim? ``X_WB``: the bin's pose if it is not where the
        scenario put it."""
        p_B = (X_WB or self.X_WB()).inverse() @ np.asarray(p_W, dtype=float)
        g = self.geometry
        return bool(
            abs(p_B[0]) < g.inner_half_x
            and abs(p_B[1]) < g.inner_half_y
            and g.floor_top < p_B[2] < g.height + 0.5
        )

    def validate(self) -> None:
        """Raises :class:`ConfigError` for a position that is not 3 numbers in the cell."""
        check_len(f"bins[{self.name}].xyz", self.xyz, 3)
        check_in_cell(f"bins[{self.name}].xyz", self.xyz)
        if self.walls:
            check_len(f"bins[{self.name}].walls", self.walls, 4)
            half_x, half_y, floor_top, height = self.walls
            if not (half_x > 0 and half_y > 0 and floor_top < height):
                raise ConfigError(
                    f"bins[{self.name}].walls {self.walls!r}: needs inner half lengths along x and y "
                    "> 0 and the floor's top below the rim"
                )


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

    def validate(self) -> None:
        """Raises :class:`ConfigError` naming the part, the bad field and its value."""
        check_len(f"parts[{self.name}].xyz", self.xyz, 3)
        check_len(f"parts[{self.name}].rpy", self.rpy, 3)
        check_in_cell(f"parts[{self.name}].xyz", self.xyz)
        if self.size <= 0 or self.mass <= 0:
            raise ConfigError(f"parts[{self.name}] needs size > 0 and mass > 0, got {self.size}, {self.mass}")


@dataclass
class ConveyorConfig:
    """The conveyor belt: its power, and where it stands (the course's pose by default;
    a student may move and turn it: its belt then runs along its new axis)."""

    #: Initial power in percent, 0...100 (belt speed = 0.2 m/s x power / 100).
    power: float = 0.0
    #: The course's helper: set the power to 0 when the break beam becomes broken.
    stop_on_beam: bool = False
    #: The conveyor's base frame on the floor: the centre of the belt's line (m), and its
    #: turn about world z (rad); at yaw 0 the belt runs toward world -y.
    xyz: list[float] = field(default_factory=lambda: [1.2, 0.0, 0.0])
    yaw: float = 0.0
    #: Its tilt (rad; roll about x, pitch about y, then yaw, as ``<pose>``): a student's world
    #: may tilt the belt, whose parts then ride along its tilted axis.
    roll: float = 0.0
    pitch: float = 0.0
    #: The belt's length and width (m) as a student's world writes its ``belt_collision``
    #: (empty: the course's, 10 x 0.6); it stands where F puts its middle.
    belt_size: list[float] = field(default_factory=list)

    def validate(self) -> None:
        if not 0 <= self.power <= 100:
            raise ConfigError(f"conveyor.power must be in [0, 100], got {self.power}")
        check_len("conveyor.xyz", self.xyz, 3)
        if self.belt_size:
            check_len("conveyor.belt_size", self.belt_size, 2)
            length, width = self.belt_size
            if not (0.2 <= length <= 30.0 and 0.05 <= width <= 3.0):
                raise ConfigError(
                    f"conveyor.belt_size {self.belt_size!r}: needs a length in [0.2, 30] and a width "
                    "in [0.05, 3] (m)"
                )
        for key in ("roll", "pitch", "yaw"):
            value = getattr(self, key)
            if not math.isfinite(value) or abs(value) > 2 * math.pi:
                raise ConfigError(f"conveyor.{key} must be an angle in [-2 pi, 2 pi] (rad), got {value}")
        if self.roll == 0.0 and self.pitch == 0.0:
            check_in_cell("conveyor.xyz", self.xyz)
        else:  # a tilted base frame may dip below the floor: its belt's middle may not
            top = self.X_WF() @ np.array([0.0, 0.0, model_dimensions("conveyor.urdf.xacro")["top"]])
            check_in_cell("conveyor (the middle of its tilted belt's top)", [float(v) for v in top])

    def X_WF(self) -> RigidTransform:
        """The conveyor's base frame F in world."""
        return RigidTransform(RollPitchYaw(self.roll, self.pitch, self.yaw), self.xyz)

    def model_args(self) -> dict[str, float]:
        """The arguments of ``models/conveyor.urdf.xacro`` for this belt (none: the course's)."""
        return {"length": self.belt_size[0], "width": self.belt_size[1]} if self.belt_size else {}


def check_pose6(what: str, pose: list[float]) -> None:
    """An optional ``x y z roll pitch yaw`` (empty: the course's pose), in the cell."""
    if pose:
        check_len(what, pose, 6)
        check_in_cell(what, pose[:3])


def pose6(pose: list[float]) -> RigidTransform:
    """``x y z roll pitch yaw`` as a transform."""
    return RigidTransform(RollPitchYaw(pose[3:6]), pose[:3])


@dataclass
class TaskConfig:
    """A pick-and-place task: which robot moves how many parts into which bin,
    seen by which cameras; and the planner's tuning.

    Heights and slots follow each part's size, which the planner takes from the
    scenario (``parts`` and ``pool_part_size``). Success: ``parts`` parts in
    ``bin`` and none lost (see omtp_drake.tasks.run).
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


def check_len(what: str, values: list[float], n: int) -> None:
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


@dataclass
class SpawnerConfig:
    """Where and when parts appear (the course's spawner and ``spawn_object_once``)."""

    #: Spawn position (world) of the part's centre.
    xyz: list[float] = field(default_factory=lambda: [1.2, 2.5, 1.021])
    #: Spawn yaw (rad) about world z.
    yaw: float = 0.0
    #: Uniform random offset in [-v, v] along world x (across the belt) and in yaw.
    lateral_variance: float = 0.0
    yaw_variance: float = 0.0
    #: Seconds between automatic spawns; 0 = only on request.
    period: float = 0.0
    #: Time of the first automatic spawn.
    start_time: float = 0.0
    #: Spawn only when no other spawned part is in the world (``spawn_object_once``).
    one_at_a_time: bool = True
    #: Stop after this many automatic spawns; 0 = no limit.
    max_parts: int = 0
    #: ros-run: the name the course's launch file gives the spawner node's
    #: ``start_spawn`` service (its remap: ``/spawn_object_once``,
    #: ``/spawn_object_at_robot2``); "" keeps ros-run's spawn-at-once services.
    start_service: str = ""
    #: ros-run: the launch file also runs the course's ``spawn_object_once.py`` node,
    #: which stops the spawner while a model named like "object" is in the world.
    stop_node: bool = False
    #: The course's plugin's objects (its ``conveyor_objects.yaml``); when given, each
    #: spawn draws one and its pose as the plugin does (:mod:`.conveyor_spawner`),
    #: instead of ``xyz``/``yaw`` and the variances above.
    objects: list[SpawnObjectConfig] = field(default_factory=list)
    #: The plugin's ``randomization_seed`` (drawn with the scenario's seed).
    randomization_seed: int = 0
    #: The plugin's ``reference_frame`` of the objects' poses: a Gazebo model or a
    #: ``model::link`` name; "" or ``world`` is the world.
    reference_frame: str = "world"

    def validate(self) -> None:
        check_len("spawner.xyz", self.xyz, 3)
        for key in ("lateral_variance", "yaw_variance", "period", "start_time"):
            value = getattr(self, key)
            if not (value >= 0 and math.isfinite(value)):
                raise ConfigError(f"spawner.{key} must be a finite number >= 0, got {value}")
        if 0 < self.period < 1.0 / MAX_RATE_HZ:
            raise ConfigError(
                f"spawner.period must be 0 (no automatic spawns) or >= {1.0 / MAX_RATE_HZ:g} s, "
                f"got {self.period}"
            )
        if self.max_parts < 0:
            raise ConfigError(f"spawner.max_parts must be >= 0, got {self.max_parts}")
        if self.start_service and (not self.start_service.startswith("/") or self.period <= 0):
            raise ConfigError(
                f"spawner.start_service {self.start_service!r} needs a global name (/...) and a period > 0 "
                f"(the spawner's timer), got period {self.period}"
            )
        if self.stop_node and not self.start_service:
            raise ConfigError("spawner.stop_node needs spawner.start_service (the spawner it stops)")
        for i, obj in enumerate(self.objects):
            obj.validate(f"spawner.objects[{i}]")


@dataclass
class SleepConfig:
    """Parts at rest fall asleep: the driver locks their joints, so the contact
    solver drops them, until something that moves touches them.

    A part falls asleep when, for ``rest_time`` seconds, its speed stayed below
    ``linear_speed`` and ``angular_speed`` while it lay on something that does
    not move (the floor, a bin, a sleeping part), touched nothing that moves (an
    arm, a cup, the belt, an awake part) and no gripper held it. It wakes when
    something that moves touches it (checked at ``check_rate_hz``) or when it is
    knocked. Physics engines do the same (Bullet's deactivation). Without it, a
    run costs more with every part that comes to rest in a bin; with it, the
    cost per simulated second stays flat (figures: bench/README.md, "Measured").
    """

    enabled: bool = True
    #: Below these speeds (m/s, rad/s) a part counts as still.
    linear_speed: float = 0.01
    angular_speed: float = 0.1
    #: How long (s) a part must stay still before it falls asleep.
    rest_time: float = 0.5
    #: How often (Hz) the driver puts parts to sleep and wakes them. 10 Hz: half the
    #: checks of 20 Hz with the same outcomes (bench/README.md, "Round five").
    check_rate_hz: float = 10.0

    def validate(self) -> None:
        for key in ("linear_speed", "angular_speed", "rest_time"):
            check_positive(f"sleep.{key}", getattr(self, key))
        check_rate("sleep.check_rate_hz", self.check_rate_hz)


@dataclass
class FrameConfig:
    """A fixed frame of the cell beyond its pieces' own: a link of a student's URDF that
    none of the cell's pieces has (``world_interface``, a camera mount...), so tf has it."""

    name: str = "frame"
    #: The frame it is fixed to (``world`` or any frame of the cell).
    parent: str = "world"
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])

    def validate(self) -> None:
        """Raises :class:`ConfigError` naming the frame, the bad field and its value."""
        check_len(f"frames[{self.name}].xyz", self.xyz, 3)
        check_len(f"frames[{self.name}].rpy", self.rpy, 3)
        if not self.parent:
            raise ConfigError(f"frames[{self.name}].parent must name a frame (e.g. world)")

    def X_PF(self) -> RigidTransform:
        """The frame's pose in its parent."""
        return RigidTransform(RollPitchYaw(self.rpy), self.xyz)
