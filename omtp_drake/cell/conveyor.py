"""The conveyor belt and the break beam.

Belt mechanism: the conveyor model has a moving contact surface, the body
``conveyor_belt``, on a prismatic joint along world y driven by a SAP
velocity servo (a PD-controlled actuator with zero position gain). Parts
resting on it are carried by ordinary friction, so they move exactly along
the belt (no sideways drift) and stop with it; parts elsewhere are untouched.
The surface extends upstream beyond the drawn belt so it can travel; the
runtime shifts it back between advances (a shift along its own length changes
no contact). :class:`ConveyorBelt` holds the power in its Context and turns it
into the servo's desired state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import RigidBody
from pydrake.systems.framework import BasicVector, Context, DiscreteValues, InputPort, LeafSystem, OutputPort

from omtp_drake.assets import model_dimensions
from omtp_drake.errors import ConfigError

#: Belt speed at power 100 (m/s), toward world -y.
MAX_SPEED = 0.2
#: The belt surface may travel this far (m) before the driver shifts it back.
WRAP_TRAVEL = 0.5
#: ``X_WF`` of the conveyor's base frame: on the floor, on the belt's centre line.
X_W_CONVEYOR = RigidTransform([1.2, 0.0, 0.0])


def belt_desired_state(power: float) -> list[float]:
    """The belt joint's desired [position, velocity] at ``power`` percent: the
    surface runs toward -y at MAX_SPEED at full power."""
    return [0.0, -MAX_SPEED * power / 100.0]


@dataclass(frozen=True)
class BeltGeometry:
    """Where the drawn belt is in world, from ``models/conveyor.urdf.xacro``."""

    #: World x of the centre line, half the width (m).
    x: float
    half_width: float
    #: World y range (m) of the drawn belt.
    y_min: float
    y_max: float
    #: World height (m) of the top surface.
    top: float

    @classmethod
    def from_model(cls) -> BeltGeometry:
        d = model_dimensions("conveyor.urdf.xacro")
        p = X_W_CONVEYOR.translation()
        return cls(
            x=float(p[0]),
            half_width=d["width"] / 2,
            y_min=float(p[1]) - d["length"] / 2,
            y_max=float(p[1]) + d["length"] / 2,
            top=float(p[2]) + d["top"],
        )

    def over(self, p_W: np.ndarray) -> bool:
        """Is the world point over the belt (within its footprint, above its top)?"""
        return bool(
            abs(p_W[0] - self.x) <= self.half_width
            and self.y_min <= p_W[1] <= self.y_max
            and p_W[2] > self.top
        )


def check_power(power: float) -> float:
    """``power`` as a float, or ConfigError unless it is in [0, 100]."""
    power = float(power)
    if not 0.0 <= power <= 100.0 or math.isnan(power):
        raise ConfigError(f"conveyor power must be in [0, 100] (percent), got {power}")
    return power


class ConveyorBelt(LeafSystem):
    """The belt's power and, optionally, the break-beam stop helper.

    Input ports:
      - ``beam`` (vector [detected, range]): the break beam's state; used only
        with ``stop_on_beam``.

    Output ports:
      - ``desired_state`` (vector [q, v]): for the belt joint's velocity servo;
        v = -0.2 m/s x power / 100 (q is ignored: the position gain is 0).
      - ``power`` (vector [power]): percent.

    State: discrete [power, last beam detection]. The power is set from outside
    between advances with :meth:`set_power`; with ``stop_on_beam``, a periodic
    check at ``beam_check_rate_hz`` sets it to 0 when the beam becomes broken
    (a rising edge, so a user may restart the belt to push a part through).
    """

    def __init__(
        self, initial_power: float = 0.0, *, stop_on_beam: bool = False, beam_check_rate_hz: float = 10.0
    ):
        super().__init__()
        check_power(initial_power)
        if beam_check_rate_hz <= 0:
            raise ConfigError(f"beam_check_rate_hz must be > 0, got {beam_check_rate_hz}")
        self._state = self.DeclareDiscreteState(np.array([initial_power, 0.0]))
        self._beam = self.DeclareVectorInputPort("beam", 2)
        self._desired_state_port = self.DeclareVectorOutputPort(
            "desired_state", 2, self._calc_desired_state, prerequisites_of_calc={self.xd_ticket()}
        )
        self._power_port = self.DeclareVectorOutputPort(
            "power",
            1,
            lambda c, out: out.SetAtIndex(0, c.get_discrete_state(self._state)[0]),
            prerequisites_of_calc={self.xd_ticket()},
        )
        self._stop_on_beam = stop_on_beam
        if stop_on_beam:
            self.DeclarePeriodicDiscreteUpdateEvent(1.0 / beam_check_rate_hz, 0.0, self._check_beam)

    def beam_input_port(self) -> InputPort:
        return self._beam

    def desired_state_output_port(self) -> OutputPort:
        return self._desired_state_port

    def power_output_port(self) -> OutputPort:
        return self._power_port

    def _calc_desired_state(self, context: Context, output: BasicVector) -> None:
        output.SetFromVector(belt_desired_state(context.get_discrete_state(self._state)[0]))

    def _check_beam(self, context: Context, discrete_state: DiscreteValues) -> None:
        power, was_detected = context.get_discrete_state(self._state).value()
        detected = float(self._beam.Eval(context)[0] > 0.5)
        if detected and not was_detected:
            power = 0.0
        discrete_state.set_value(self._state, [power, detected])

    def set_power(self, context: Context, power: float) -> None:
        """Sets the power (percent); out of [0, 100] raises and changes nothing."""
        power = check_power(power)
        value = context.get_discrete_state(self._state).value().copy()
        value[0] = power
        context.SetDiscreteState(self._state, value)

    def power(self, context: Context) -> float:
        return float(context.get_discrete_state(self._state)[0])


class BreakBeam(LeafSystem):
    """A break-beam sensor: is anything on the segment [min_range, max_range] of its beam?

    Input port ``plant_state`` (vector): the plant's state [q; v].
    Output port ``state`` (vector [detected, range]), sampled at ``rate_hz`` and
    held: detected is 1.0 when a candidate body's bounding box crosses the
    beam segment; range is the distance from the emitter to the nearest hit
    (inf when clear).

    Frames: the beam leaves the plant frame ``frame`` (``break_beam_optical_link``,
    fixed to the world) along its +x axis. Candidates: the given free bodies (on a
    quaternion floating joint, e.g. the parts), each with an axis-aligned box in its
    own frame (centre, half-extents). Their poses are read straight from the state
    vector, and only bodies within reach of the segment get the exact test.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        frame,
        bodies: list[RigidBody],
        boxes: list[tuple[np.ndarray, np.ndarray]],
        *,
        rate_hz: float = 10.0,
        min_range: float = 0.1,
        max_range: float = 0.6,
    ):
        super().__init__()
        if rate_hz <= 0 or not 0 <= min_range < max_range:
            raise ConfigError(
                f"break beam needs rate_hz > 0 and 0 <= min_range < max_range, got "
                f"{rate_hz}, {min_range}, {max_range}"
            )
        if len(bodies) != len(boxes):
            raise ConfigError("break beam: one box per body")
        if not plant.IsAnchored(frame.body()):
            raise ConfigError(f"break beam: its frame {frame.name()!r} must be fixed to the world")
        X_WE = frame.CalcPoseInWorld(plant.CreateDefaultContext())
        self._p_WE = X_WE.translation()
        self._u_W = X_WE.rotation().col(0)
        starts = []
        for body in bodies:
            if not body.is_floating_base_body() or not body.has_quaternion_dofs():
                raise ConfigError(f"break beam: candidate {body.name()!r} must be a free body")
            starts.append(body.floating_positions_start())
        # q[start: start + 4] is the quaternion (w, x, y, z), q[start + 4: start + 7] the position.
        self._quaternion_index = np.array([[k + i for i in range(4)] for k in starts], dtype=np.intp).reshape(
            -1, 4
        )
        self._position_index = np.array(
            [[k + 4 + i for i in range(3)] for k in starts], dtype=np.intp
        ).reshape(-1, 3)
        self._centres = np.array([c for c, _ in boxes], dtype=float).reshape(-1, 3)
        self._halves = np.array([h for _, h in boxes], dtype=float).reshape(-1, 3)
        # A body farther than this from the segment cannot touch it.
        self._reach = np.linalg.norm(self._centres, axis=1) + np.linalg.norm(self._halves, axis=1)
        self._range = (min_range, max_range)
        self._plant_state = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self._state = self.DeclareDiscreteState(np.array([0.0, np.inf]))
        self.DeclarePeriodicDiscreteUpdateEvent(1.0 / rate_hz, 0.0, self._update)
        self.DeclareInitializationDiscreteUpdateEvent(self._update)
        self._state_port = self.DeclareStateOutputPort("state", self._state)

    def plant_state_input_port(self) -> InputPort:
        return self._plant_state

    def state_output_port(self) -> OutputPort:
        """[detected, range], as last sampled."""
        return self._state_port

    @property
    def p_WE(self) -> np.ndarray:
        """Where the beam starts (its frame E's origin) in the world."""
        return self._p_WE.copy()

    @property
    def u_W(self) -> np.ndarray:
        """The beam's direction (E's +x axis) in the world; ranges are measured along it."""
        return self._u_W.copy()

    def read(self, context: Context) -> np.ndarray:
        """[detected, range] at the state in ``context``."""
        x = self._plant_state.Eval(context)
        p_WB = x[self._position_index]  # (n, 3)
        lo, hi = self._range
        # Distance of each body origin to the segment: only those within reach are tested.
        t = np.clip((p_WB - self._p_WE) @ self._u_W, lo, hi)
        gap = np.linalg.norm(p_WB - (self._p_WE + t[:, None] * self._u_W), axis=1)
        near = np.flatnonzero(gap <= self._reach)
        if not len(near):
            return np.array([0.0, np.inf])
        R_WB = _rotations(x[self._quaternion_index[near]])  # (n, 3, 3)
        # Slab test of the beam segment against each body's box, in the box's frame.
        R_BW = R_WB.transpose(0, 2, 1)
        origin = (R_BW @ (self._p_WE - p_WB[near])[:, :, None])[:, :, 0] - self._centres[near]
        direction = R_BW @ self._u_W  # (n, 3)
        half = self._halves[near]
        parallel = np.abs(direction) < 1e-12
        outside = np.any(parallel & (np.abs(origin) > half), axis=1)  # parallel to a slab, outside it
        d = np.where(parallel, 1.0, direction)
        t1, t2 = (-half - origin) / d, (half - origin) / d
        t_near = np.max(np.where(parallel, -np.inf, np.minimum(t1, t2)), axis=1)
        t_far = np.min(np.where(parallel, np.inf, np.maximum(t1, t2)), axis=1)
        hit = ~outside & (t_near <= t_far) & (t_far >= lo) & (t_near <= hi)
        if not hit.any():
            return np.array([0.0, np.inf])
        return np.array([1.0, float(np.max([np.min(t_near[hit]), lo]))])

    def _update(self, context: Context, discrete_state: DiscreteValues) -> None:
        discrete_state.set_value(self._state, self.read(context))


def _rotations(q: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation matrices of the quaternions ``q`` (n, 4) = (w, x, y, z),
    normalised first."""
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=1,
    )
