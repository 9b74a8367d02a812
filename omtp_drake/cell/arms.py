"""The classic UR arms: the course's named poses, loading, and position control.

Each arm is position-controlled like a real UR: desired joint positions in,
measured state out. Inside, a discrete derivative turns the position command
into a desired state and Drake's ``InverseDynamicsController`` (computed torque
with a model of the arm plus its gripper) tracks it, so gravity is compensated.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.controllers import InverseDynamics, InverseDynamicsController
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, OutputPort
from pydrake.systems.primitives import Demultiplexer, LinearSystem, MatrixGain, Multiplexer
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.cell.described_models import add_described_models
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario import ModelConfig, RobotConfig
from omtp_drake.ur_arms import model_rates, ur_urdf

#: Joint order of every pose: pan, lift, elbow, wrist 1, wrist 2, wrist 3.
JOINT_NAMES = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)

#: The course's named poses (radians), by their course names.
NAMED_POSES: Mapping[str, tuple[float, ...]] = {
    "R1Up": (0.0, -1.5708, 0.0, -1.5708, 0.0, 0.0),
    "R1Home": (1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0.0),
    "R1PreGrasp": (0.785398, -1.5708, 1.5708, -1.5708, -1.5708, 0.0),
    "R1Place": (-1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0.0),
    "R2Up": (0.0, -1.5708, 0.0, -1.5708, 0.0, 0.0),
    "R2Home": (1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0.0),
    "R2PreGrasp": (0.785398, -1.5708, 1.5708, -1.5708, -1.5708, 0.0),
    "R2Place": (2.5952, -1.161, 0.7512, -1.2293, -1.5708, 0.0),
}


def named_pose(name: str, robot: RobotConfig | None = None) -> np.ndarray:
    """Joint positions of a named pose.

    ``name`` is a course name (``R2Place``) or, with ``robot``, a short name
    resolved with the robot's prefix (``Place`` -> ``R2Place`` for robot 2).
    With ``robot``, only that robot's poses are valid.
    """
    if robot is None:
        if name not in NAMED_POSES:
            raise UnknownNameError("named pose", name, NAMED_POSES)
        return np.array(NAMED_POSES[name])
    own = {k: v for k, v in NAMED_POSES.items() if k.startswith(robot.pose_prefix)}
    key = name if name in own else robot.pose_prefix + name
    if key not in own:
        valid = list(own) + [k[len(robot.pose_prefix) :] for k in own]
        raise UnknownNameError(f"named pose of {robot.name}", name, valid, closest=True)
    return np.array(own[key])


def check_joint_positions(q, robot: RobotConfig) -> np.ndarray:
    """``q`` as 6 finite joint positions within ``robot``'s limits, or ConfigError."""
    try:
        q = np.asarray(q, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ConfigError(
            f"joint positions of {robot.name} must be {len(JOINT_NAMES)} numbers "
            f"({', '.join(JOINT_NAMES)}), got {q!r}"
        ) from None
    if q.shape != (len(JOINT_NAMES),):
        raise ConfigError(
            f"joint positions of {robot.name} must be {len(JOINT_NAMES)} numbers "
            f"({', '.join(JOINT_NAMES)}), got {len(q)}: {q.tolist()}"
        )
    if not np.all(np.isfinite(q)):
        raise ConfigError(f"joint positions of {robot.name} must be finite, got {q.tolist()}")
    limits = robot.limits()
    outside = np.flatnonzero(np.abs(q) > limits + 1e-9)
    if len(outside):
        i = int(outside[0])
        raise ConfigError(
            f"joint {JOINT_NAMES[i]} of {robot.name} at {q[i]:.4f} rad is outside "
            f"its limits [-{limits[i]:.4f}, {limits[i]:.4f}] rad"
        )
    return q


def arm_urdf(robot: RobotConfig) -> Path:
    """The URDF of ``robot``'s arm: its model's, with the position, velocity and effort
    limits, the links' inertials and the geometry its scenario gives."""
    return ur_urdf(
        robot.model,
        robot.name + "_",
        joint_limit=robot.limits(),
        velocity=robot.velocity_limits,
        effort=robot.effort_limits,
        inertials=robot.inertials,
        dropped=robot.own_geometry,
    )


def gripper_urdf(robot: RobotConfig) -> str:
    """The URDF text of ``robot``'s vacuum gripper (without collisions where its file has none)."""
    args = {"name": robot.gripper, "collision": "true" if robot.gripper_collision else "false"}
    return expand_xacro(MODELS_DIR / "vacuum_gripper.urdf.xacro", args)


def joint_velocity_limits(robot: RobotConfig) -> np.ndarray:
    """``robot``'s joint velocity limits (rad/s, pan ... wrist 3): its scenario's, else its
    model's (ur_description's, :func:`omtp_drake.ur_arms.model_rates`)."""
    return np.array(robot.velocity_limits or model_rates(robot.model)[0], dtype=float)


def add_arm_models(
    parser: Parser, robot: RobotConfig
) -> tuple[ModelInstanceIndex, ModelInstanceIndex | None]:
    """Adds the arm (and its gripper, welded to tool0) to ``parser``'s plant.

    The arm's base is not welded: the caller places it.
    Returns (arm instance, gripper instance or None).
    """
    plant = parser.plant()
    (arm,) = parser.AddModels(str(arm_urdf(robot)))
    gripper = None
    if robot.gripper:
        (gripper,) = parser.AddModelsFromString(gripper_urdf(robot), "urdf")
        plant.WeldFrames(
            plant.GetFrameByName(f"{robot.name}_tool0", arm),
            plant.GetFrameByName(f"{robot.gripper}_base_link", gripper),
        )
    return arm, gripper


def lock_arm(plant: MultibodyPlant, plant_context: Context, arm: ModelInstanceIndex, locked: bool) -> None:
    """Locks (or unlocks) the moving joints of the model instance ``arm`` where they
    are: a locked arm does not move whatever its servo commands."""
    for index in plant.GetJointIndices(arm):
        joint = plant.get_joint(index)
        if joint.num_velocities() > 0:
            if locked:
                joint.Lock(plant_context)
            else:
                joint.Unlock(plant_context)


def make_control_plant(
    robot: RobotConfig, gravity: Sequence[float], payloads: Sequence[ModelConfig] = ()
) -> MultibodyPlant:
    """A continuous plant of the arm alone (plus its gripper and the ``payloads`` hung on
    them: model entries whose ``parent`` is one of their links), base welded at the origin.

    Used for inverse dynamics and differential IK. The pedestal only translates
    and yaws the base, so ``gravity`` (the factory's, in world) is rotated into
    the base frame: the model sees the same gravity as the arm in the factory.
    """
    plant = MultibodyPlant(time_step=0.0)
    g_W = np.asarray(gravity, dtype=float)
    plant.mutable_gravity_field().set_gravity_vector(base_pose(robot).rotation().inverse() @ g_W)
    arm, _ = add_arm_models(Parser(plant), robot)
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(f"{robot.name}_base_link", arm))
    add_described_models(Parser(plant), list(payloads))
    plant.Finalize()
    return plant


class CommandSampler:
    """Samples an arm's position command at the servo's rate into a consistent
    reference: position, velocity and acceleration of the same instant.

    One discrete linear system (C++) keeps the last three samples ``q_k, q_{k-1},
    q_{k-2}`` (period ``h``) and outputs, all centred on the middle sample::

        q_d = q_{k-1}
        v_d = (q_k - q_{k-2}) / 2h
        a_d = (q_k - 2 q_{k-1} + q_{k-2}) / h^2

    The reference is one sample late, but never out of step with itself. Drake's
    StateInterpolatorWithDiscreteDerivative passes the newest sample as the position
    while its velocity is the difference of the two before it; a derivative of that
    velocity, sampled at the same instants, is another sample behind. During an
    acceleration such a servo lags and then catches up faster than commanded: the cup
    overshoots a plan's speed (figures: bench/README.md, "Measured").

    Input port ``position`` (n); output ports ``desired_state`` (2n, ``[q_d; v_d]``)
    and ``desired_acceleration`` (n).
    """

    def __init__(self, builder: DiagramBuilder, n: int, period: float, name: str):
        h, eye, zero = period, np.eye(n), np.zeros((n, n))
        shift = np.block([[zero, zero, zero], [eye, zero, zero], [zero, eye, zero]])
        newest = np.vstack([eye, zero, zero])
        reference = np.block(
            [
                [zero, eye, zero],
                [eye / (2 * h), zero, -eye / (2 * h)],
                [eye / h**2, -2 * eye / h**2, eye / h**2],
            ]
        )
        self._samples = builder.AddNamedSystem(
            f"{name}.command_samples",
            LinearSystem(shift, newest, reference, np.zeros((3 * n, n)), time_period=period),
        )
        self._split = builder.AddNamedSystem(f"{name}.desired_state", Demultiplexer([2 * n, n]))
        builder.Connect(self._samples.get_output_port(), self._split.get_input_port())

    def connect_input(self, builder: DiagramBuilder, name: str) -> None:
        """Exports the command input as ``name`` on ``builder``'s diagram."""
        builder.ExportInput(self._samples.get_input_port(), name)

    def connect_from(self, builder: DiagramBuilder, command: OutputPort) -> None:
        """Feeds the sampler from ``command`` (an output port in ``builder``)."""
        builder.Connect(command, self._samples.get_input_port())

    def get_output_port(self) -> OutputPort:
        """``desired_state`` ``[q_d; v_d]``."""
        return self._split.get_output_port(0)

    def get_acceleration_output_port(self) -> OutputPort:
        """``desired_acceleration`` ``a_d``."""
        return self._split.get_output_port(1)

    def set_initial_position(self, root_context: Context, q: np.ndarray) -> None:
        """At rest at ``q``: every remembered sample is ``q``."""
        context = self._samples.GetMyMutableContextFromRoot(root_context)
        context.SetDiscreteState(np.tile(np.asarray(q, dtype=float), 3))


def add_arm_controller(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    arm: ModelInstanceIndex,
    robot: RobotConfig,
    gravity: Sequence[float],
    *,
    payloads: Sequence[ModelConfig] = (),
) -> tuple[CommandSampler, Diagram, MultibodyPlant]:
    """Adds the position servo of one arm and connects it to ``plant``.

    The command is sampled at ``robot.command_rate_hz`` into a consistent desired
    state (:class:`CommandSampler`); the servo is computed torque on a model of the
    arm and its gripper: desired accelerations ``kp (q_d - q) + kd (v_d - v)`` (plus
    ``ki`` times their integral when ``robot.ki > 0``, Drake's
    InverseDynamicsController) through inverse dynamics, so gravity is compensated.
    Without an integral it has no continuous state (which the simulator would have
    to integrate: about 20 % of a run).

    Returns the command sampler (its input is the arm's position command; the
    caller exports it), the servo (a diagram with inputs ``estimated_state``,
    ``desired_state`` and output ``actuation``), and the servo's model of the arm
    (under ``gravity``, the factory's). The caller must keep that plant alive as
    long as the diagram: the servo only refers to it (pydrake does not keep it
    alive; a collected plant crashes the simulation).
    """
    control_plant = make_control_plant(robot, gravity, payloads)
    n = control_plant.num_positions()
    if robot.ki > 0:
        servo: Diagram = InverseDynamicsController(
            control_plant,
            kp=np.full(n, robot.kp),
            ki=np.full(n, robot.ki),
            kd=np.full(n, robot.kd),
            has_reference_acceleration=False,
        )
    else:
        servo = _pd_inverse_dynamics(control_plant, robot.kp, robot.kd)
    servo.set_name(f"{robot.name}.controller")
    builder.AddSystem(servo)
    sampler = CommandSampler(builder, n, 1.0 / robot.command_rate_hz, robot.name)
    builder.Connect(plant.get_state_output_port(arm), servo.GetInputPort("estimated_state"))
    builder.Connect(sampler.get_output_port(), servo.GetInputPort("desired_state"))
    if servo.HasInputPort("desired_acceleration"):
        builder.Connect(sampler.get_acceleration_output_port(), servo.GetInputPort("desired_acceleration"))
    builder.Connect(servo.GetOutputPort("actuation"), plant.get_actuation_input_port(arm))
    return sampler, servo, control_plant


def _pd_inverse_dynamics(control_plant: MultibodyPlant, kp: float, kd: float) -> Diagram:
    """Stateless computed torque with acceleration feed-forward, all C++:
    ``ID(q, v, a_d + kp (q_d - q) + kd (v_d - v))``. Without ``a_d`` the joints lag
    ``a / kp`` behind each acceleration and then catch up faster than commanded (about
    ``0.37 a / sqrt(kp)``: 15 % over a 1 m/s plan's cruise)."""
    n = control_plant.num_positions()
    builder = DiagramBuilder()
    mux = builder.AddNamedSystem("signals", Multiplexer([2 * n, 2 * n, n]))  # [x_d; x; a_d]
    eye = np.eye(n)
    gains = np.hstack([kp * eye, kd * eye, -kp * eye, -kd * eye, eye])
    pd = builder.AddNamedSystem("pd", MatrixGain(gains))
    inverse_dynamics = builder.AddNamedSystem(
        "inverse_dynamics",
        InverseDynamics(control_plant, InverseDynamics.InverseDynamicsMode.kInverseDynamics),
    )
    builder.Connect(mux.get_output_port(), pd.get_input_port())
    builder.Connect(pd.get_output_port(), inverse_dynamics.GetInputPort("desired_acceleration"))
    builder.ExportInput(mux.get_input_port(0), "desired_state")
    builder.ExportInput(mux.get_input_port(1), "estimated_state")
    builder.ExportInput(mux.get_input_port(2), "desired_acceleration")
    builder.ConnectInput("estimated_state", inverse_dynamics.GetInputPort("estimated_state"))
    builder.ExportOutput(inverse_dynamics.GetOutputPort("generalized_force"), "actuation")
    return builder.Build()


#: The smallest elbow bend (rad) a reachable pose may need: a straighter arm is near
#: its elbow singularity, where differential IK stalls.
MIN_ELBOW_BEND = 0.4


@functools.cache
def _tool_down_envelope(model: str, gripper: str) -> tuple[np.ndarray, np.ndarray]:
    """(heights, radii): for cup-face heights above the arm's base (2 cm bins), the
    largest horizontal distance from the base axis at which the tip can point straight
    down with the elbow bent at least MIN_ELBOW_BEND (forward kinematics of the arm
    in the plane of its lift, elbow and wrist 1 joints)."""
    robot = RobotConfig(name="reach", model=model, gripper=gripper)
    plant = make_control_plant(robot, (0.0, 0.0, -9.8))
    context = plant.CreateDefaultContext()
    tip = plant.GetFrameByName(f"{gripper}_tip" if gripper else "reach_tool0")
    heights = np.arange(-1.6, 1.6, 0.02)
    radii = np.full(len(heights), -np.inf)
    for lift in np.linspace(-math.pi, math.pi / 6, 120):
        for elbow in np.linspace(MIN_ELBOW_BEND, 2.9, 60):
            plant.SetPositions(context, [0.0, lift, elbow, -math.pi / 2 - lift - elbow, -math.pi / 2, 0.0])
            p = tip.CalcPoseInWorld(context).translation()
            k = int(round((p[2] - heights[0]) / 0.02))
            if 0 <= k < len(heights):
                radii[k] = max(radii[k], math.hypot(p[0], p[1]))
    return heights, radii


def tool_down_reach(robot: RobotConfig, z_W: float) -> float:
    """The largest horizontal distance (m) from ``robot``'s base axis at which its cup
    face can be at world height ``z_W`` pointing straight down, with the elbow bent
    enough to stay clear of its singularity (-inf: that height is out of reach)."""
    heights, radii = _tool_down_envelope(robot.model, robot.gripper)
    z_B = z_W - robot.pedestal_height  # the base's height (base_pose)
    k = int(round((z_B - heights[0]) / 0.02))
    if not 0 <= k < len(heights):
        return -math.inf
    # The neighbouring bins too: the sampling leaves gaps.
    return float(np.max(radii[max(0, k - 1) : k + 2]))


def tool_frame_names(robot: RobotConfig) -> dict[str, str]:
    """The arm's tool frames by short name -> their names in the plant: ``tip`` (the
    cup face) and ``suction_cup`` (the course's frame) with a gripper, and ``tool0``."""
    names = {"tool0": f"{robot.name}_tool0"}
    if robot.gripper:
        names = {"tip": f"{robot.gripper}_tip", "suction_cup": f"{robot.gripper}_suction_cup", **names}
    return names


def base_pose(robot: RobotConfig) -> RigidTransform:
    """``X_WB``: the arm's base_link on top of its pedestal."""
    x, y = robot.xy
    return RigidTransform(RollPitchYaw(0.0, 0.0, robot.yaw), [x, y, robot.pedestal_height])


def joint_trajectory(
    robot: RobotConfig,
    poses: list[str],
    *,
    start_time: float = 0.0,
    dwell: float = 0.5,
    speed_fraction: float = 0.5,
    velocity_limits: np.ndarray | None = None,
) -> PiecewisePolynomial:
    """A smooth joint-space trajectory through named poses, at rest at each one.

    Each move is a cubic with zero end velocities whose duration keeps every
    joint under ``speed_fraction`` of its velocity limit (a cubic peaks at 1.5x
    its mean speed); the arm then dwells ``dwell`` seconds.
    """
    if len(poses) < 1:
        raise ConfigError("joint_trajectory needs at least one pose")
    if not 0 < speed_fraction <= 1:
        raise ConfigError(f"speed_fraction must be in (0, 1], got {speed_fraction}")
    vmax = np.asarray(
        velocity_limits if velocity_limits is not None else joint_velocity_limits(robot), dtype=float
    )
    qs = [named_pose(p, robot) for p in poses]
    times, knots = [start_time], [qs[0]]

    def add(duration: float, q: np.ndarray) -> None:
        if duration > 0:
            times.append(times[-1] + duration)
            knots.append(q)

    for q in qs[1:]:
        add(dwell, knots[-1])
        add(max(0.5, float(np.max(1.5 * np.abs(q - knots[-1]) / (speed_fraction * vmax)))), q)
    add(dwell, knots[-1])
    if len(times) == 1:
        add(1e-3, knots[-1])
    zero = np.zeros(6)
    segments = []
    for i in range(len(times) - 1):
        segments.append(
            PiecewisePolynomial.CubicHermite(
                [times[i], times[i + 1]],
                np.column_stack([knots[i], knots[i + 1]]),
                np.column_stack([zero, zero]),
            )
        )
    trajectory = segments[0]
    for segment in segments[1:]:
        trajectory.ConcatenateInTime(segment)
    return trajectory
