"""A rig to exercise a vacuum gripper outside the factory (tests and benchmarks).

The rig: a world HalfSpace floor, a "tool" carried by x, y, z prismatic joints
and yaw, tilt revolute joints, each driven by a stiff SAP PD actuator that
tracks a scripted trajectory (simulated time), the course's vacuum gripper
welded to the tool with its cup pointing down (world -z), and 0.2 m cube parts
on the floor. :meth:`Rig.advance_to` advances the simulator in chunks and calls
``sync_weld`` after each chunk, as the driver does.

Example::

    rig = build_rig("weld", hold(tool_q(0, 0, TOP - PRESS)))
    rig.command(True)
    rig.advance_to(0.2)
    assert rig.state().attached
"""

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
from pydrake.geometry import HalfSpace
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import (
    AddMultibodyPlant,
    CoulombFriction,
    MultibodyPlant,
    MultibodyPlantConfig,
)
from pydrake.multibody.tree import (
    ModelInstanceIndex,
    PdControllerGains,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    SpatialInertia,
)
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, Diagram, DiagramBuilder
from pydrake.systems.primitives import TrajectorySource
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.cell.suction import GripperState, SuctionGripper, contact_points
from omtp_drake.cell.suction_constraints import declare_suction_constraints
from omtp_drake.cell.suction_holds import (
    WeldSuctionGripper,
    add_suction_gripper,
    connect_spatial_forces,
    sync_weld,
)
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import Scenario, SuctionConfig

H = Scenario().plant_config.time_step  # plant step [s]: the station's
CHUNK = 0.05  # driver chunk = the runtime's tick [s]
#: The tool's motions are sampled this often [s], whatever the plant's step, so that
#: rigs at different steps follow the same motion.
MOTION_DT = 0.005
SIZE = 0.2  # part edge [m]
PART_Z = SIZE / 2 + 0.001  # a part's centre resting on its 1 mm corner spheres
TOP = SIZE + 0.001  # its top face
CUP_OFFSET = 0.0775  # tool0 -> cup face along the gripper's +z (world -z here)
PRESS = 0.002  # how far the cup face is commanded into the part
GRIPPER = "vacuum_gripper1"
# The tool's joints (positions q): x, y, z (tool0's world position), yaw
# about world z, tilt about the tool's x axis (0 = cup straight down).


# ----------------------------------------------------------------------------
# Rig


@dataclass
class Rig:
    """The rig's diagram, its simulator and its parts (see :func:`build_rig`)."""

    diagram: Diagram
    plant: MultibodyPlant
    gripper: SuctionGripper
    parts: list[RigidBody]
    simulator: Simulator
    context: Context
    #: (time, X_WP of parts[0], X_WC) after every simulator step: every plant
    #: step, plus a chunk's end when it falls between two steps.
    log: list = field(default_factory=list)

    @property
    def plant_context(self) -> Context:
        return self.plant.GetMyContextFromRoot(self.context)

    @property
    def time_step(self) -> float:
        """The plant's step [s] (:data:`H` unless the rig was built with another)."""
        return self.plant.time_step()

    @property
    def time(self) -> float:
        return self.context.get_time()

    def command(self, on: bool) -> None:
        self.gripper.command_input_port().FixValue(
            self.gripper.GetMyMutableContextFromRoot(self.context), [1.0 if on else 0.0]
        )

    def state(self) -> GripperState:
        return self.gripper.state_output_port().Eval(self.gripper.GetMyContextFromRoot(self.context))

    def X_WP(self, i: int = 0) -> RigidTransform:
        return self.plant.EvalBodyPoseInWorld(self.plant_context, self.parts[i])

    def X_WC(self) -> RigidTransform:
        return self.plant.EvalBodyPoseInWorld(
            self.plant_context, self.plant.get_body(self.gripper.cup_body_index)
        )

    def advance_to(
        self, t: float, chunk: float = CHUNK, after: Optional[Callable[["Rig"], None]] = None
    ) -> None:
        """The driver's loop: advance in chunks, sync the weld after each."""
        while self.time < t - 1e-9:
            k = math.floor(self.time / chunk + 1e-9) + 1
            self.simulator.AdvanceTo(min(t, k * chunk))
            if isinstance(self.gripper, WeldSuctionGripper):
                sync_weld(self.gripper, self.plant, self.context)
            if after is not None:
                after(self)

    def held_body(self) -> Optional[int]:
        """Weld backend: the body index the constraints hold (None: inactive)."""
        held = self.gripper.constraints.held_body(self.plant, self.plant_context)
        return None if held is None else int(held)

    def cup_part_contacts(self) -> int:
        """Point contacts between the cup and the first part now."""
        return contact_points(
            self.plant, self.plant_context, self.gripper.cup_body_index, self.parts[0].index()
        )


def tool_q(x: float, y: float, cup_z: float, yaw: float = 0.0, tilt: float = 0.0) -> np.ndarray:
    """Joint positions putting the cup face centre at (x, y, cup_z) (before tilt)."""
    return np.array([x, y, cup_z + CUP_OFFSET, yaw, tilt])


def trajectory(
    waypoints: Sequence[tuple[float, np.ndarray]], accel: float = 20.0, dt: float = MOTION_DT
) -> PiecewisePolynomial:
    """Straight segments between (time, q) waypoints, each with a trapezoidal speed.

    Each segment starts and ends at rest and accelerates at ``accel`` (m/s^2 or
    rad/s^2) up to the cruise speed that makes it last its duration; a huge
    ``accel`` gives steps in velocity. Sampled every ``dt`` (first-order hold).
    """
    times, qs = [waypoints[0][0]], [np.asarray(waypoints[0][1], float)]
    for (t0, q0), (t1, q1) in zip(waypoints, waypoints[1:]):
        q0, q1 = np.asarray(q0, float), np.asarray(q1, float)
        T, D = t1 - t0, float(np.max(np.abs(q1 - q0)))
        n = max(1, int(round(T / dt)))
        for k in range(1, n + 1):
            s = _trapezoid(k * T / n, T, D, accel) / D if D > 0 else 1.0
            times.append(t0 + k * T / n)
            qs.append(q0 + s * (q1 - q0))
    return PiecewisePolynomial.FirstOrderHold(times, np.array(qs).T)


def _trapezoid(t: float, T: float, D: float, a: float) -> float:
    """Distance covered at t by a rest-to-rest trapezoid of length D in time T."""
    # cruise speed v with ramps of v / a: D = v T - v^2 / a.
    disc = T * T - 4 * D / a
    if disc < 0:
        raise ConfigError(f"cannot cover {D} in {T} s at an acceleration of {a}")
    v = (T - math.sqrt(disc)) * a / 2
    tr = v / a
    if t < tr:
        return 0.5 * a * t * t
    if t > T - tr:
        return D - 0.5 * a * (T - t) ** 2
    return 0.5 * a * tr * tr + v * (t - tr)


def plant_config(
    time_step: Optional[float] = None, near_rigid_threshold: Optional[float] = None
) -> MultibodyPlantConfig:
    """The station's plant settings (SAP point contact, unsampled output ports),
    with ``time_step`` [s] and SAP's ``sap_near_rigid_threshold`` instead of the
    station's when given.

    Raises ConfigError for a step the scenario would refuse (its range check).
    """
    scenario = Scenario()
    config = (scenario if time_step is None else scenario.with_time_step(time_step)).plant_config
    if near_rigid_threshold is not None:
        if not near_rigid_threshold >= 0:
            raise ConfigError(f"near_rigid_threshold must be >= 0, got {near_rigid_threshold}")
        config.sap_near_rigid_threshold = near_rigid_threshold
    return config


def build_rig(
    backend: str,
    motion: PiecewisePolynomial,
    *,
    parts: Sequence[tuple[float, float, float]] = ((0.0, 0.0, 0.0),),
    mass: float = 0.2,
    config: Optional[SuctionConfig] = None,
    log: bool = True,
    time_step: Optional[float] = None,
    near_rigid_threshold: Optional[float] = None,
    collision: bool = True,
) -> Rig:
    """The rig with parts at (x, y, yaw) on the floor, the tool following ``motion``
    (a trajectory of :func:`tool_q` positions); the gripper's command is off.

    ``time_step`` [s] and ``near_rigid_threshold`` replace the station's plant step
    and SAP near-rigid threshold (None keeps them); see :func:`plant_config`. Without
    ``collision`` the gripper has no collisions (a student's gripper file with none).
    """
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(plant_config(time_step, near_rigid_threshold), builder)
    plant.RegisterCollisionGeometry(
        plant.world_body(), RigidTransform(), HalfSpace(), "floor", CoulombFriction(1.0, 1.0)
    )
    tool, tool_body = _add_tool(plant)
    parser = Parser(plant)
    _add_gripper(plant, parser, tool_body, collision)
    part_bodies = _add_parts(plant, parser, parts, mass)
    cup = plant.GetBodyByName(f"{GRIPPER}_cup")
    config = config or SuctionConfig(backend=backend)
    constraints = declare_suction_constraints(plant, cup, part_bodies[0]) if backend == "weld" else None
    plant.Finalize()

    source = builder.AddSystem(TrajectorySource(motion, output_derivative_order=1))
    builder.Connect(source.get_output_port(), plant.get_desired_state_input_port(tool))
    gripper = add_suction_gripper(builder, plant, cup, part_bodies, config, "suction1", constraints)
    connect_spatial_forces(builder, plant, [gripper])
    diagram = builder.Build()

    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    plant.SetPositions(plant_context, tool, motion.value(motion.start_time()).ravel())
    if constraints is not None:
        constraints.deactivate_all(plant, plant_context)
    simulator = Simulator(diagram, context)
    rig = Rig(diagram, plant, gripper, part_bodies, simulator, context)
    if log:
        _log_poses(rig, cup)
    rig.command(False)
    simulator.Initialize()
    return rig


def _add_tool(plant: MultibodyPlant) -> tuple[ModelInstanceIndex, RigidBody]:
    """The tool's model instance: x, y, z prismatic and yaw, tilt revolute joints
    from the world, each with a stiff PD actuator; returns it and its last body."""
    tool = plant.AddModelInstance("tool")
    light = SpatialInertia.SolidBoxWithMass(0.1, 0.05, 0.05, 0.05)
    links = [plant.AddRigidBody(n, tool, light) for n in ("tool_x", "tool_y", "tool_z", "tool_yaw")]
    links.append(plant.AddRigidBody("tool", tool, SpatialInertia.SolidBoxWithMass(0.5, 0.05, 0.05, 0.05)))
    parents = [plant.world_body()] + links[:-1]
    joints = [
        PrismaticJoint("jx", parents[0].body_frame(), links[0].body_frame(), [1, 0, 0]),
        PrismaticJoint("jy", parents[1].body_frame(), links[1].body_frame(), [0, 1, 0]),
        PrismaticJoint("jz", parents[2].body_frame(), links[2].body_frame(), [0, 0, 1]),
        RevoluteJoint("jyaw", parents[3].body_frame(), links[3].body_frame(), [0, 0, 1]),
        RevoluteJoint("jtilt", parents[4].body_frame(), links[4].body_frame(), [1, 0, 0]),
    ]
    for joint in joints:
        joint = plant.AddJoint(joint)
        actuator = plant.AddJointActuator(joint.name(), joint)
        actuator.set_controller_gains(PdControllerGains(p=1e6, d=2e4))
    return tool, links[-1]


def _add_gripper(plant: MultibodyPlant, parser: Parser, tool_body: RigidBody, collision: bool = True) -> None:
    """The course's vacuum gripper, welded to ``tool_body`` with its cup pointing down."""
    args = {"name": GRIPPER, "collision": "true" if collision else "false"}
    (gripper_instance,) = parser.AddModelsFromString(
        expand_xacro(MODELS_DIR / "vacuum_gripper.urdf.xacro", args), "urdf"
    )
    # Cup down: the gripper's +z (out of the tool) along world -z.
    plant.WeldFrames(
        tool_body.body_frame(),
        plant.GetFrameByName(f"{GRIPPER}_base_link"),
        RigidTransform(RollPitchYaw(math.pi, 0, 0), [0, 0, 0]),
    )


def _add_parts(
    plant: MultibodyPlant, parser: Parser, parts: Sequence[tuple[float, float, float]], mass: float
) -> list[RigidBody]:
    """Free cube parts ``part_<i>`` resting on the floor at (x, y, yaw); their bodies."""
    part_bodies = []
    for i, (x, y, yaw) in enumerate(parts):
        (instance,) = parser.AddModelsFromString(
            expand_xacro(MODELS_DIR / "part.urdf.xacro", {"name": f"part_{i}", "size": SIZE, "mass": mass}),
            "urdf",
        )
        body = plant.GetBodyByName(f"part_{i}", instance)
        plant.SetDefaultFloatingBaseBodyPose(body, RigidTransform(RollPitchYaw(0, 0, yaw), [x, y, PART_Z]))
        part_bodies.append(body)
    return part_bodies


def _log_poses(rig: Rig, cup: RigidBody) -> None:
    """Appends (time, X_WP of the first part, X_WC) to ``rig.log`` after every simulator step."""
    plant, part = rig.plant, rig.parts[0]

    def monitor(root: Context):
        pc = plant.GetMyContextFromRoot(root)
        rig.log.append(
            (
                root.get_time(),
                plant.EvalBodyPoseInWorld(pc, part),
                plant.EvalBodyPoseInWorld(pc, cup),
            )
        )

    rig.simulator.set_monitor(monitor)


def hold(q: np.ndarray, until: float = 5.0) -> PiecewisePolynomial:
    """The tool at ``q`` until ``until``."""
    return trajectory([(0.0, q), (until, q)])


def pick_motion(accel: float) -> tuple[PiecewisePolynomial, float, float]:
    """Press on a part, lift 0.3 m, carry 0.6 m and back, at 1 m/s with ``accel``
    [m/s^2] ramps; returns (motion, t_moving, t_stop): the lift starts at
    t_moving, the tool is at rest again from t_stop."""
    down = tool_q(0.02, 0.01, TOP - PRESS)
    up = down + [0, 0, 0.3, 0, 0]
    far = up + [0.6, 0, 0, 0, 0]
    side = far + [0, -0.4, 0, math.radians(20), 0]
    back = side - [0.6, 0, 0, 0, 0]
    ramp = 1.0 / accel
    lift, carry, turn = 0.3 + ramp, 0.6 + ramp, 0.4 + ramp
    t0 = 0.3
    waypoints = [
        (0.0, down),
        (t0, down),
        (t0 + lift, up),
        (t0 + lift + carry, far),
        (t0 + lift + carry + turn, side),
        (t0 + lift + 2 * carry + turn, back),
        (t0 + lift + 2 * carry + turn + 0.3, back),
    ]
    return trajectory(waypoints, accel=accel), t0, waypoints[-2][0]


def pose_change(X_a: RigidTransform, X_b: RigidTransform) -> tuple[float, float]:
    """(distance [m], angle [deg]) between two poses."""
    angle = X_a.rotation().InvertAndCompose(X_b.rotation()).ToAngleAxis().angle()
    return float(np.linalg.norm(X_a.translation() - X_b.translation())), math.degrees(angle)


def logged_at(rig: Rig, t: float) -> tuple[RigidTransform, RigidTransform]:
    """(X_WP, X_WC) logged at time t (the step ending at t)."""
    for time, X_WP, X_WC in rig.log:
        if abs(time - t) < 1e-9:
            return X_WP, X_WC
    raise ConfigError(f"no log entry at t = {t} (the log has {len(rig.log)} steps)")
