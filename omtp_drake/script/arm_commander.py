"""The system that feeds an arm's position servo: :class:`ArmCommander`, and the
command a script gives it (:class:`JointCommand`).

The :class:`~omtp_drake.script.cell.Cell` adds one commander per arm to the
diagram; the arm's moves (:mod:`omtp_drake.script.motion`) set its command
between the simulator's advances.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, DiscreteValues, LeafSystem, OutputPort
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.cell import arms
from omtp_drake.scenario import RobotConfig


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


class ArmCommander(LeafSystem):
    """Feeds an arm's position servo with a joint trajectory that a script sets.

    .. pydrake_system::

        name: ArmCommander
        output_ports:
        - position

    Output port ``position`` (vector, 6, :meth:`position_output_port`): the
    trajectory sampled at ``rate_hz`` (the servo's command rate) and held, so
    the servo reads a cached value between samples (no Python per plant step).

    State: abstract, the command (:class:`JointCommand`: a trajectory and its start
    time, or a position to hold); discrete, the sampled position. A script sets a
    new command between advances with :meth:`command`.
    """

    def __init__(self, robot: RobotConfig):
        super().__init__()
        self.set_name(f"{robot.name}.commander")
        q0 = arms.named_pose(robot.initial_pose, robot)
        self._command = self.DeclareAbstractState(AbstractValue.Make(JointCommand(q0)))
        self._q = self.DeclareDiscreteState(q0)
        self._position_port = self.DeclareStateOutputPort("position", self._q)
        self.DeclarePeriodicDiscreteUpdateEvent(1.0 / robot.command_rate_hz, 0.0, self._sample)
        self.DeclareInitializationDiscreteUpdateEvent(self._sample)

    def position_output_port(self) -> OutputPort:
        """The ``position`` output: the sampled joint positions for the arm's servo."""
        return self._position_port

    def _sample(self, context: Context, discrete_state: DiscreteValues) -> None:
        command: JointCommand = context.get_abstract_state(self._command).get_value()
        discrete_state.set_value(self._q, command.at(context.get_time()))

    def command(self, context: Context, command: JointCommand) -> None:
        """The new command, from now on (the sampled position follows at the next sample)."""
        context.SetAbstractState(self._command, command)

    def hold(self, context: Context, q: np.ndarray) -> None:
        """Hold ``q`` from now, the sampled position too (not only from the next sample)."""
        q = np.array(q, dtype=float)
        context.SetAbstractState(self._command, JointCommand(q))
        context.SetDiscreteState(self._q, q)

    def current(self, context: Context) -> JointCommand:
        return context.get_abstract_state(self._command).get_value()

    def commanded_position(self, context: Context) -> np.ndarray:
        """The position the servo is being sent now."""
        return context.get_discrete_state(self._q).value().copy()
