"""The system that feeds an arm's position servo: :class:`ArmCommander`, and the
command a script gives it (:class:`JointCommand`).

The :class:`~omtp_drake.script.cell.Cell` adds one commander per arm to the
diagram; the arm's moves (:mod:`omtp_drake.script.motion`) set its command
between the simulator's advances. The command lives in the Context, so each
Context of one diagram plays its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, DiscreteValues, LeafSystem, OutputPort
from pydrake.systems.primitives import AffineSystem, Demultiplexer
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.control.joint_plan import JerkStream, JointPlan
from omtp_drake.scenario import RobotConfig

#: The commander's period ``H`` (s): its plan's knots are this far apart, and it writes
#: the jerk of the plan's next piece this often (the pick-and-place machine's 20 Hz).
#: Against the commanded trajectories sampled at every tick, the plan strays at most
#: bench/README.md's "Script commands in the Context" figures.
PERIOD = 0.05


@dataclass(frozen=True)
class JointCommand:
    """What an arm is told to do: follow ``trajectory`` (its own time axis, shifted by
    ``t0``), then hold its end; or hold ``q`` when there is none."""

    q: np.ndarray
    trajectory: Optional[PiecewisePolynomial] = None
    t0: float = 0.0

    def __deepcopy__(self, memo: dict) -> JointCommand:
        return self  # immutable: Drake clones abstract state on every update

    def at(self, t: float) -> np.ndarray:
        if self.trajectory is None:
            return self.q
        tau = min(max(t - self.t0, self.trajectory.start_time()), self.trajectory.end_time())
        return self.trajectory.value(tau).ravel()


class _CommandPlayer(LeafSystem):
    """The command a script gave (abstract state: the :class:`JointCommand` and the
    :class:`~omtp_drake.control.joint_plan.JointPlan` that plays it) and the jerk of the
    plan's current piece (discrete state, output ``jerk``), written at every multiple of
    ``period``."""

    def __init__(self, q0: np.ndarray, period: float):
        super().__init__()
        self.command = self.DeclareAbstractState(AbstractValue.Make(JointCommand(q0)))
        self.plan = self.DeclareAbstractState(AbstractValue.Make(JointPlan.hold(0.0, period, q0)))
        self.jerk = self.DeclareDiscreteState(len(q0))
        self.DeclareStateOutputPort("jerk", self.jerk)
        plan = self.plan  # (C++ holds the callback: it must not hold self)

        def write_jerk(context: Context, state: DiscreteValues) -> None:
            jerk = context.get_abstract_state(plan).get_value().jerk(context.get_time())
            state.get_mutable_vector(0).SetFromVector(jerk)

        self.DeclarePeriodicDiscreteUpdateEvent(period, 0.0, write_jerk)


class ArmCommander(Diagram):
    """Feeds an arm's position servo with the joint command a script sets, played in
    Drake's C++ between the commander's updates.

    .. pydrake_system::

        name: ArmCommander
        output_ports:
        - position

    Output port ``position`` (vector, 6, :meth:`position_output_port`): the command
    sampled every ``h = 1 / command_rate_hz`` (the servo's command rate) and held.

    How: a command's trajectory becomes a :class:`~omtp_drake.control.joint_plan.JointPlan`
    when it is given (knots every :data:`PERIOD` on the simulator's time axis, C2 from
    the played state), kept in the Context (abstract state, with the command itself:
    what :meth:`current` reads); every :data:`PERIOD` an update writes the jerk of its
    next piece, which a :class:`~omtp_drake.control.joint_plan.JerkStream` (C++)
    integrates exactly at every ``h``. After the stream's update at a tick ``t`` the
    position is the plan's at ``t``, the trajectory's sample there as before up to the
    plan's smoothing (at most the figures in bench/README.md), so two Contexts of
    one diagram play their own commands.
    """

    def __init__(self, robot: RobotConfig):
        super().__init__()
        q0 = arms.named_pose(robot.initial_pose, robot)
        n = len(q0)
        self._h = 1.0 / robot.command_rate_hz
        self._period = self._h * max(1, round(PERIOD / self._h))
        builder = DiagramBuilder()
        self._player = builder.AddNamedSystem("command", _CommandPlayer(q0, self._period))
        self._stream = builder.AddNamedSystem("stream", JerkStream(q0, self._h, self._period, "stream"))
        split = builder.AddNamedSystem("position", Demultiplexer([n, 2 * n]))
        # The time of the stream's last tick (x+ = x + h at the stream's ticks, from the
        # tick before 0): whether the simulator has run the tick it stopped at.
        self._clock = builder.AddNamedSystem(
            "clock",
            AffineSystem(
                np.eye(1),
                np.zeros((1, 0)),
                [self._h],
                np.eye(1),
                np.zeros((1, 0)),
                [0.0],
                time_period=self._h,
            ),
        )
        self._clock.configure_default_state([-self._h])
        builder.Connect(self._player.get_output_port(), self._stream.get_input_port())
        builder.Connect(self._stream.get_output_port(), split.get_input_port())
        builder.ExportOutput(split.get_output_port(0), "position")
        builder.BuildInto(self)
        self.set_name(f"{robot.name}.commander")
        self._integrator = self._stream.GetSubsystemByName("integrator")
        self._jerk_hold = self._stream.GetSubsystemByName("jerk_hold")

    def position_output_port(self) -> OutputPort:
        """The ``position`` output: the sampled joint positions for the arm's servo."""
        return self.get_output_port(0)

    def command(self, context: Context, command: JointCommand) -> None:
        """The new command, from now on: the position follows it from the next tick on
        (a command without a trajectory: holds ``q`` from now, see :meth:`hold`)."""
        if command.trajectory is None:
            self.hold(context, command.q)
            return
        H = self._period
        # The stream's state is the plan's at its last tick, its jerk the held one until
        # the next grid point after that tick, where the player writes the next.
        t_last = self._last_tick(context)
        t0 = H * (math.floor(t_last / H + 1e-9))
        knots = _knots(command.trajectory, command.t0, t0, H)
        plan = JointPlan.through(t0, H, self._played(context), knots, at=t_last)
        self._set(context, command, plan, plan.jerk(t_last))

    def hold(self, context: Context, q: np.ndarray) -> None:
        """Hold ``q`` from now, the sampled position too (not only from the next tick)."""
        q = np.array(q, dtype=float)
        self._set(context, JointCommand(q), JointPlan.hold(context.get_time(), self._period, q), 0 * q)
        self._stream_context(context).SetDiscreteState(np.concatenate([q, 0 * q, 0 * q]))

    def current(self, context: Context) -> JointCommand:
        player = self.GetSubsystemContext(self._player, context)
        return player.get_abstract_state(self._player.command).get_value()

    def commanded_position(self, context: Context) -> np.ndarray:
        """The position the servo is being sent now."""
        played = self._played(context)
        return played[: len(played) // 3].copy()

    def _last_tick(self, context: Context) -> float:
        """The time of the stream's last update: the simulator stops before the updates
        due at the time it stops at, and runs them when asked to advance to that time again."""
        h, t = self._h, context.get_time()
        clock = self.GetSubsystemContext(self._clock, context).get_discrete_state_vector()[0]
        t_last = h * round(clock / h)
        if not t - h - 1e-9 <= t_last <= t + 1e-9:  # a Context whose time was set by hand
            t_last = h * (math.ceil(t / h - 1e-9) - 1)
        return t_last

    def _played(self, context: Context) -> np.ndarray:
        """The stream's [q; v; a]."""
        stream = self.GetSubsystemContext(self._stream, context)
        return self._stream.GetSubsystemContext(self._integrator, stream).get_discrete_state_vector().value()

    def _stream_context(self, context: Context) -> Context:
        stream = self.GetMutableSubsystemContext(self._stream, context)
        return self._stream.GetMutableSubsystemContext(self._integrator, stream)

    def _set(self, context: Context, command: JointCommand, plan: JointPlan, jerk: np.ndarray) -> None:
        """The command and its plan, and ``jerk`` played from the next tick until the
        player's next update (its own state and the stream's held copy)."""
        player = self.GetMutableSubsystemContext(self._player, context)
        player.SetAbstractState(self._player.command, command)
        player.SetAbstractState(self._player.plan, plan)
        player.SetDiscreteState(jerk)
        stream = self.GetMutableSubsystemContext(self._stream, context)
        self._stream.GetMutableSubsystemContext(self._jerk_hold, stream).SetDiscreteState(jerk)


def _knots(trajectory: PiecewisePolynomial, shift: float, t0: float, period: float) -> np.ndarray:
    """``trajectory`` (its time axis shifted right by ``shift``) at ``t0 + m period``
    (m = 1 ... until its end), held at its ends."""
    start, end = trajectory.start_time(), trajectory.end_time()
    m = max(1, math.ceil((shift + end - t0) / period - 1e-9))
    tau = np.clip(t0 + period * np.arange(1, m + 1) - shift, start, end)
    return np.vstack([trajectory.value(x).ravel() for x in tau])
