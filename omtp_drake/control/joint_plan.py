"""Joint plans integrated ahead: a tool path turned into joints when it is decided, and
played by Drake's C++ between decisions.

When the pick-and-place machine decides a tool path (:class:`~omtp_drake.control.tool_paths.Path`),
:class:`DiffIkAhead` runs Drake's differential IK (``DoDifferentialInverseKinematics``,
the parameters of the ``DifferentialInverseKinematicsIntegrator`` the controller used
before: joint velocity and position limits, Home as the nominal posture, its centering
gain) over the path's time grid at once: one knot per controller period ``H``, each from
``substeps`` DiffIK steps. :class:`JointPlan` is the C2 uniform cubic B-spline through
those knots (a local quasi-interpolant, so a wrong start never rings along the plan),
starting from the command's position, velocity and acceleration when it is decided and
ending at rest. Each of its pieces is one cubic of constant jerk, so
:class:`JerkStream` (a discrete ``LinearSystem``, C++) integrates the plan exactly at
the command rate from the jerk of the current piece, which the controller's output gives
once per period (the plan's, from the Context): between two periods no Python runs at
the plant step.

Frames: W world, B the arm's base_link, E the tool frame (``<gripper>_tip``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.inverse_kinematics import (
    DifferentialInverseKinematicsParameters,
    DifferentialInverseKinematicsStatus,
    DoDifferentialInverseKinematics,
)
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.primitives import LinearSystem, ZeroOrderHold
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.control.tool_paths import Path
from omtp_drake.scenario import RobotConfig

#: DiffIK steps per knot. Against the 100 Hz integrator on lecture6_assignment4's paths,
#: the commanded tool strays at most 2.94 mm with one step per 50 ms knot, 2.05 mm with
#: two (and three), for 1.7x the QPs (bench/README.md, "DiffIK integrated ahead"). One:
#: the tool at every decision of the machine stays within 0.7 mm of two steps' (the
#: equivalence test's 2 mm), for half the QPs (bench/README.md, "Round five").
SUBSTEPS = 1


def diffik_parameters(
    robot: RobotConfig, n: int, time_step: float
) -> DifferentialInverseKinematicsParameters:
    """Drake's DiffIK parameters of ``robot``'s arm: the arm's joint velocity and position
    limits, joints centred on Home (gain 0.05), at ``time_step``."""
    params = DifferentialInverseKinematicsParameters(n, n)
    params.set_time_step(time_step)
    vmax = arms.joint_velocity_limits(robot)
    params.set_joint_velocity_limits((-vmax, vmax))
    params.set_joint_position_limits((-robot.limits(), robot.limits()))
    params.set_nominal_joint_position(arms.named_pose("Home", robot))
    params.set_joint_centering_gain(0.05 * np.eye(n))
    return params


class DiffIkAhead:
    """Integrates Drake's DiffIK along a tool path at decision time (see the module doc).

    Args:
        plant: the arm's model (base at the origin: frame B).
        robot: the arm (its limits and Home).
        X_WB: the arm's base in the world.
        period: ``H``, the time between knots (s).
        substeps: DiffIK steps per knot.
    """

    def __init__(
        self, plant: MultibodyPlant, robot: RobotConfig, X_WB: RigidTransform, period: float, substeps: int
    ):
        self._plant = plant
        self._context = plant.CreateDefaultContext()
        self._tip = plant.GetFrameByName(f"{robot.gripper}_tip")
        self._X_BW = X_WB.inverse()
        self._dt = period / substeps
        self._substeps = substeps
        self._params = diffik_parameters(robot, plant.num_positions(), self._dt)

    def knots(self, path: Path, q: np.ndarray, t0: float, period: float, lag: float) -> np.ndarray:
        """Joint positions at ``t0 + m period`` (m = 1 ... M) from ``q`` at ``t0``, each
        DiffIK step towards the path ``lag`` s earlier than its end (the integrator's
        one-step delay), until the path's end pose is asked for."""
        dt = self._dt
        steps = self._substeps * max(1, math.ceil((path.end_time + lag - t0) / period - 1e-9))
        p_WE, R_WE = path.poses(t0 + dt * np.arange(1, steps + 1) - lag)
        R_BW, p_BW = self._X_BW.rotation().matrix(), self._X_BW.translation()
        R_BE, p_BE = R_BW @ R_WE, p_WE @ R_BW.T + p_BW
        q = np.array(q, dtype=float)
        out = np.empty((steps // self._substeps, len(q)))
        plant, context, tip, params = self._plant, self._context, self._tip, self._params
        for k in range(steps):
            plant.SetPositions(context, q)
            X_BE = RigidTransform(RotationMatrix(R_BE[k]), p_BE[k])
            result = DoDifferentialInverseKinematics(plant, context, X_BE, tip, params)
            if result.status != DifferentialInverseKinematicsStatus.kNoSolutionFound:
                q = q + dt * result.joint_velocities
            if (k + 1) % self._substeps == 0:
                out[k // self._substeps] = q
        return out


@dataclass(frozen=True)
class JointPlan:
    """A joint plan: the uniform cubic B-spline of ``control`` points (knot spacing
    ``period``, its first piece starting at ``t0``), at rest at its last point after
    :attr:`end_time` and at its start before ``t0``. Immutable: it lives in a Context's
    abstract state.

    Piece ``i`` (from ``t0 + i period``) is the cubic of control points ``i`` to ``i + 3``;
    its jerk is constant (:meth:`jerk`)."""

    t0: float
    period: float
    control: np.ndarray = field(repr=False)

    @staticmethod
    def hold(t0: float, period: float, q: np.ndarray) -> JointPlan:
        """At rest at ``q``."""
        return JointPlan(t0, period, np.tile(np.asarray(q, dtype=float), (4, 1)))

    @staticmethod
    def through(t0: float, period: float, start: np.ndarray, knots: np.ndarray) -> JointPlan:
        """From ``start`` = [q; v; a] at ``t0`` (C2: the command's state there) near
        ``knots[m - 1]`` at ``t0 + m period``, at rest at the last knot two periods after it.

        The first three control points give ``start``; the others are the quasi-interpolant
        ``(-K[j-1] + 8 K[j] - K[j+1]) / 6`` of the knots (K[0] = q, the last knot repeated),
        which a cubic through the knots reproduces."""
        H = period
        q0, v0, a0 = np.split(np.asarray(start, dtype=float), 3)
        K = np.vstack([q0, knots, np.tile(knots[-1], (4, 1))])  # K[m]: at t0 + m period
        Q = np.empty((len(knots) + 5, len(q0)))  # Q[j] is centred on t0 + (j - 1) period
        Q[0] = q0 + H * H * a0 / 3 - H * v0
        Q[1] = q0 - H * H * a0 / 6
        Q[2] = q0 + H * H * a0 / 3 + H * v0
        Q[3:] = (-K[1:-2] + 8 * K[2:-1] - K[3:]) / 6
        return JointPlan(t0, period, Q)

    @property
    def pieces(self) -> int:
        return len(self.control) - 3

    @property
    def end_time(self) -> float:
        """From then on the plan rests at its last control point."""
        return self.t0 + self.pieces * self.period

    def _piece(self, t: float) -> tuple[int, float]:
        """The piece covering ``t`` and where in it (0 to 1), clamped to the plan."""
        u = (t - self.t0) / self.period
        i = min(max(math.floor(u + 1e-9), 0), self.pieces - 1)
        return i, min(max(u - i, 0.0), 1.0)

    @cached_property
    def _jerks(self) -> np.ndarray:
        """Each piece's jerk (rows), worked out once: :meth:`jerk` is asked at every
        update of the controller."""
        Q = self.control
        return (-Q[:-3] + 3 * Q[1:-2] - 3 * Q[2:-1] + Q[3:]) / self.period**3

    def jerk(self, t: float) -> np.ndarray:
        """The joints' jerk on the piece covering ``t`` (zero outside the plan)."""
        u = (t - self.t0) / self.period
        i = math.floor(u + 1e-9)
        if not 0 <= i < self.pieces:
            return np.zeros(self.control.shape[1])
        return self._jerks[i].copy()

    def state(self, t: float) -> np.ndarray:
        """[q; v; a] at ``t``."""
        i, u = self._piece(t)
        Q, H = self.control[i : i + 4], self.period
        b = np.array([(1 - u) ** 3, 3 * u**3 - 6 * u**2 + 4, -3 * u**3 + 3 * u**2 + 3 * u + 1, u**3]) / 6
        db = np.array([-3 * (1 - u) ** 2, 9 * u**2 - 12 * u, -9 * u**2 + 6 * u + 3, 3 * u**2]) / (6 * H)
        ddb = np.array([6 * (1 - u), 18 * u - 12, -18 * u + 6, 6 * u]) / (6 * H * H)
        at_rest = t < self.t0 or t >= self.end_time
        return np.concatenate(
            [b @ Q, (0.0 if at_rest else 1.0) * (db @ Q), (0.0 if at_rest else 1.0) * (ddb @ Q)]
        )

    def trajectory(self) -> PiecewisePolynomial:
        """The plan as a PiecewisePolynomial (exact: cubic Hermite pieces)."""
        times = self.t0 + self.period * np.arange(self.pieces + 1)
        states = [self.state(t) for t in times[:-1]] + [self.state(times[-1] - 1e-12)]
        n = self.control.shape[1]
        q = np.column_stack([s[:n] for s in states])
        v = np.column_stack([s[n : 2 * n] for s in states])
        return PiecewisePolynomial.CubicHermite(times, q, v)

    def __deepcopy__(self, memo: dict) -> JointPlan:
        return self  # immutable: Drake clones abstract state at every update


def jerk_dynamics(n: int, h: float) -> tuple[np.ndarray, np.ndarray]:
    """(A, B) of [q; v; a] under a jerk held for ``h`` (exact)."""
    eye, zero = np.eye(n), np.zeros((n, n))
    A = np.block([[eye, h * eye, h * h / 2 * eye], [zero, eye, h * eye], [zero, zero, eye]])
    B = np.vstack([h**3 / 6 * eye, h * h / 2 * eye, h * eye])
    return A, B


class JerkStream(Diagram):
    """Plays a :class:`JointPlan` from the jerk of its pieces, all in C++: a
    ``ZeroOrderHold`` samples the input jerk once per ``period``, at the controller's
    update times, and a discrete ``LinearSystem`` (step ``h``) integrates it exactly
    into [q; v; a].

    Order at an update time ``t``: Drake's simulator makes the unrestricted updates (the
    controller's, which may decide a new plan, so a new jerk) before the discrete ones, and computes all the
    discrete ones (the hold's sample, the integrator's step) from the state before any
    is applied: the hold samples the new jerk, and the integrator's step from ``t``
    still plays the old one. So the hold at ``t`` plays as one at ``t + h / 2`` did,
    with no event time of its own (20 fewer simulator stops per simulated second at
    20 Hz, each a pass over the whole diagram's events; bench/README.md).

    .. pydrake_system::

        name: JerkStream
        input_ports:
        - jerk
        output_ports:
        - state

    Its state starts at rest at ``q0``; the jerk sampled at ``t`` is played from
    ``t + h`` to ``t + period + h``.
    """

    def __init__(self, q0: np.ndarray, h: float, period: float, name: str):
        super().__init__()
        n = len(q0)
        builder = DiagramBuilder()
        hold = builder.AddNamedSystem("jerk_hold", ZeroOrderHold(period, n))
        A, B = jerk_dynamics(n, h)
        stream = builder.AddNamedSystem(
            "integrator", LinearSystem(A, B, np.eye(3 * n), np.zeros((3 * n, n)), time_period=h)
        )
        stream.configure_default_state(np.concatenate([q0, np.zeros(2 * n)]))
        builder.Connect(hold.get_output_port(), stream.get_input_port())
        builder.ExportInput(hold.get_input_port(), "jerk")
        builder.ExportOutput(stream.get_output_port(), "state")
        builder.BuildInto(self)
        self.set_name(name)


class PlanAhead:
    """The controller's motion: a new :class:`JointPlan` when the machine decides a tool
    path, and the jerk to play at each of its periods.

    Timing: the controller decides at ``t`` (a multiple of ``period``); the
    :class:`JerkStream` plays the jerk sampled then from ``t + h`` on, so a plan decided
    at ``t`` starts at ``t + h`` from the played plan's state there (which the stream
    follows exactly), and its piece ``i`` is the jerk sampled at ``t + i period``.

    Args:
        plant: the arm's model (base at the origin).
        robot: the arm.
        X_WB: its base in the world.
        period: the controller's period ``H`` (a whole number of ``h``).
        h: the jerk stream's (and DiffIK's) step: DiffIK targets the path ``h`` earlier,
            as the ``DifferentialInverseKinematicsIntegrator`` did (its output at
            ``t + h`` was its step towards the path at ``t``).
        substeps: DiffIK steps per knot.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        robot: RobotConfig,
        X_WB: RigidTransform,
        period: float,
        h: float,
        substeps: int = SUBSTEPS,
    ):
        self.period, self.h = period, h
        self._ahead = DiffIkAhead(plant, robot, X_WB, period, substeps)

    def plan(self, path: Path, t: float, played: JointPlan, q_from: np.ndarray | None = None) -> JointPlan:
        """The plan of ``path`` decided at ``t``, following on from ``played`` (the plan
        being played: C2 at ``t + h``, where the new one starts), DiffIK integrated from
        the command's position there or from ``q_from`` (the measured joints, to
        restart there)."""
        t0 = t + self.h
        start = played.state(t0)
        n = len(start) // 3
        q = start[:n] if q_from is None else q_from
        if not path.segments:
            return JointPlan.through(t0, self.period, start, start[None, :n])
        knots = self._ahead.knots(path, q, t0, self.period, lag=self.h)
        return JointPlan.through(t0, self.period, start, knots)

    def jerk(self, plan: JointPlan, t: float) -> np.ndarray:
        """The jerk to play from an update at ``t``: the plan's from ``t + h`` on."""
        return plan.jerk(t + self.h)
