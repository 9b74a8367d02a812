"""The conveyor belt and the break beam.

Belt mechanism: the conveyor model has a moving contact surface, the body
``conveyor_belt``, on a prismatic joint along its base frame's y driven by a SAP
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
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import RigidBody
from pydrake.systems.framework import BasicVector, Context, DiscreteValues, InputPort, LeafSystem, OutputPort

from omtp_drake.assets import model_dimensions
from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.parts import free_body_q_indices
from omtp_drake.errors import ConfigError
from omtp_drake.scenario.configs import ConveyorConfig

#: Belt speed at power 100 (m/s), toward world -y.
MAX_SPEED = 0.2
#: The belt surface may travel this far (m) before the driver shifts it back.
WRAP_TRAVEL = 0.5
#: ``X_WF`` of the conveyor's base frame where the course has it: on the floor, on the
#: belt's centre line (a scenario may move it: ``ConveyorConfig.xyz``/``yaw``).
X_W_CONVEYOR = ConveyorConfig().X_WF()


def belt_desired_state(power: float) -> list[float]:
    """The belt joint's desired [position, velocity] at ``power`` percent: the
    surface runs toward -y at MAX_SPEED at full power."""
    return [0.0, -MAX_SPEED * power / 100.0]


@dataclass(frozen=True)
class BeltGeometry:
    """Where the drawn belt is, from ``models/conveyor.urdf.xacro`` placed at ``X_WF`` (its
    base frame F: the belt's centre line runs along F's y, its parts move toward F's -y,
    its top surface faces F's +z). F may be tilted (a student's world turns the conveyor
    about x or y): the belt's top is then a tilted plane, and "above" means along F's z."""

    #: Half the belt's width and length (m), in F.
    half_width: float
    half_length: float
    #: Height (m) of the top surface above F's origin, along F's z.
    top_F: float
    X_WF: RigidTransform = X_W_CONVEYOR

    @classmethod
    def from_model(cls, X_WF: RigidTransform = X_W_CONVEYOR, size: Sequence[float] = ()) -> BeltGeometry:
        """The catalogue's belt at ``X_WF``, ``size`` (length, width) long and wide when given."""
        d = model_dimensions("conveyor.urdf.xacro")
        length, width = size if len(size) == 2 else (d["length"], d["width"])
        return cls(width / 2, length / 2, d["top"], X_WF)

    @classmethod
    def of(cls, conveyor: ConveyorConfig) -> BeltGeometry:
        """The belt of the scenario's ``conveyor``: where and as long and wide as it is."""
        return cls.from_model(conveyor.X_WF(), conveyor.belt_size)

    @property
    def top(self) -> float:
        """World height (m) of the top surface at the middle of the belt's centre line."""
        return float((self.X_WF @ np.array([0.0, 0.0, self.top_F]))[2])

    @property
    def centre(self) -> np.ndarray:
        """The belt's centre line's middle, in world (x, y)."""
        return self.X_WF.translation()[:2].copy()

    @property
    def x(self) -> float:
        """World x of the centre line's middle (the centre line of a belt along world y)."""
        return float(self.X_WF.translation()[0])

    @property
    def direction(self) -> np.ndarray:
        """The way parts ride (world, unit): F's -y (tilted with the belt)."""
        return -self.X_WF.rotation().col(1)

    @property
    def normal(self) -> np.ndarray:
        """The top surface's outward normal (world, unit): F's +z."""
        return self.X_WF.rotation().col(2)

    def height(self, p_W: np.ndarray) -> float:
        """How far (m) the world point is above the belt's top surface, along its normal."""
        return float((self.X_WF.inverse() @ np.asarray(p_W, dtype=float))[2]) - self.top_F

    def over(self, p_W: np.ndarray) -> bool:
        """Is the world point over the belt (within its footprint, above its top)?"""
        p_F = self.X_WF.inverse() @ np.asarray(p_W, dtype=float)
        return bool(
            abs(p_F[0]) <= self.half_width and abs(p_F[1]) <= self.half_length and p_F[2] > self.top_F
        )

    def resting_point(self, p_W: np.ndarray, support: float, clearance: float = 0.001) -> np.ndarray:
        """Where a part's centre rests on the belt under (or over) the world point ``p_W``:
        ``support`` (m) plus ``clearance`` above the top surface along its normal (``support``:
        the part's extent from its centre to its lowest point along that normal)."""
        p_F = self.X_WF.inverse() @ np.asarray(p_W, dtype=float)
        p_F[2] = self.top_F + support + clearance
        return self.X_WF @ p_F


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
        # C++ holds the calc callbacks: none may keep self (see cell.lifetime).
        self._desired_state_port = self.DeclareVectorOutputPort(
            "desired_state",
            2,
            weak_method(self._calc_desired_state),
            prerequisites_of_calc={self.xd_ticket()},
        )
        state = self._state
        self._power_port = self.DeclareVectorOutputPort(
            "power",
            1,
            lambda c, out: out.SetAtIndex(0, c.get_discrete_state(state)[0]),
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
        #: Per candidate: the indices in q of its quaternion (w, x, y, z) and position,
        #: its box (centre, half extents, in its frame) and its reach from its origin.
        self._candidates: list[tuple[tuple[int, ...], tuple[int, ...], list[float], list[float], float]] = []
        for body, (centre, half) in zip(bodies, boxes):
            if not body.is_floating_base_body() or not body.has_quaternion_dofs():
                raise ConfigError(f"break beam: candidate {body.name()!r} must be a free body")
            q_index, p_index = free_body_q_indices(body)
            c = np.asarray(centre, dtype=float).reshape(3)
            h = np.asarray(half, dtype=float).reshape(3)
            reach = float(np.linalg.norm(c) + np.linalg.norm(h))  # farther: cannot touch the beam
            self._candidates.append((q_index, p_index, c.tolist(), h.tolist(), reach))
        self._range = (min_range, max_range)
        self._rate_hz = float(rate_hz)
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
    def rate_hz(self) -> float:
        """How often the beam samples (Hz); samples are at k / rate_hz."""
        return self._rate_hz

    @property
    def range(self) -> tuple[float, float]:
        """The beam's sensing range (min, max) in m along its axis."""
        return self._range

    @property
    def p_WE(self) -> np.ndarray:
        """Where the beam starts (its frame E's origin) in the world."""
        return self._p_WE.copy()

    @property
    def u_W(self) -> np.ndarray:
        """The beam's direction (E's +x axis) in the world; ranges are measured along it."""
        return self._u_W.copy()

    def read(self, context: Context) -> np.ndarray:
        """[detected, range] at the state in ``context``.

        In plain floats: a dozen candidates cost less than numpy's small-array calls
        between plant steps (bench/README.md)."""
        x = self._plant_state.Eval(context).tolist()
        lo, hi = self._range
        p_WE, u_W = self._p_WE.tolist(), self._u_W.tolist()
        first = math.inf
        for q_index, (i, j, k), centre, half, reach in self._candidates:
            # The body origin's distance to the segment: only those within reach get
            # the exact test.
            d = (x[i] - p_WE[0], x[j] - p_WE[1], x[k] - p_WE[2])
            t = min(max(d[0] * u_W[0] + d[1] * u_W[1] + d[2] * u_W[2], lo), hi)
            g = (d[0] - t * u_W[0], d[1] - t * u_W[1], d[2] - t * u_W[2])
            if g[0] * g[0] + g[1] * g[1] + g[2] * g[2] > reach * reach:
                continue
            q = [x[a] for a in q_index]
            first = min(first, _slab_entry(q, [x[i], x[j], x[k]], centre, half, p_WE, u_W, lo, hi))
        return np.array([0.0, np.inf]) if first == math.inf else np.array([1.0, first])

    def _update(self, context: Context, discrete_state: DiscreteValues) -> None:
        discrete_state.set_value(self._state, self.read(context))


def _slab_entry(
    q: list[float],
    p_WB: list[float],
    centre: list[float],
    half: list[float],
    p_WE: list[float],
    u_W: list[float],
    lo: float,
    hi: float,
) -> float:
    """Where the beam segment [lo, hi] from ``p_WE`` along ``u_W`` first is inside the
    box (``centre``, ``half`` extents, in frame B) of a body at ``p_WB`` with the
    quaternion ``q`` = (w, x, y, z) (normalised here): the range along the beam, at
    least ``lo``; inf when the segment misses the box (the slab test, in B)."""
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    w, x, y, z = q[0] / n, q[1] / n, q[2] / n, q[3] / n
    R_WB = (
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    )
    d = (p_WE[0] - p_WB[0], p_WE[1] - p_WB[1], p_WE[2] - p_WB[2])
    t_near, t_far = -math.inf, math.inf
    for i in range(3):  # B's axis i: column i of R_WB
        origin = R_WB[0][i] * d[0] + R_WB[1][i] * d[1] + R_WB[2][i] * d[2] - centre[i]
        direction = R_WB[0][i] * u_W[0] + R_WB[1][i] * u_W[1] + R_WB[2][i] * u_W[2]
        if abs(direction) < 1e-12:  # parallel to the slab: inside it or a miss
            if abs(origin) > half[i]:
                return math.inf
            continue
        t1, t2 = (-half[i] - origin) / direction, (half[i] - origin) / direction
        t_near, t_far = max(t_near, min(t1, t2)), min(t_far, max(t1, t2))
    if t_near <= t_far and t_far >= lo and t_near <= hi:
        return max(t_near, lo)
    return math.inf
