"""The system that feeds an arm's position servo: :class:`ArmCommander`, and the
command a script gives it (:class:`JointCommand`).

The :class:`~omtp_drake.script.cell.Cell` adds one commander per arm to the
diagram; the arm's moves (:mod:`omtp_drake.script.motion`) set its command
between the simulator's advances.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, LeafSystem, OutputPort
from pydrake.systems.primitives import LinearSystem, TrajectorySource
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


class _CommandMemory(LeafSystem):
    """The command a script gave (abstract state, :class:`JointCommand`); no ports, no events."""

    def __init__(self, q0: np.ndarray):
        super().__init__()
        self.index = self.DeclareAbstractState(AbstractValue.Make(JointCommand(q0)))


class ArmCommander(Diagram):
    """Feeds an arm's position servo with a joint trajectory that a script sets, all
    in Drake's C++ between the script's calls: no Python per sample.

    .. pydrake_system::

        name: ArmCommander
        output_ports:
        - position

    Output port ``position`` (vector, 6, :meth:`position_output_port`): the command
    sampled at ``command_rate_hz`` (the servo's command rate) and held: a
    ``TrajectorySource`` of the command's trajectory (shifted to start at its ``t0``,
    held at its ends) into a discrete hold (a ``LinearSystem`` x+ = u, y = x, its
    default state the initial pose).

    State: the command (:class:`JointCommand`, abstract, in the Context: what
    :meth:`current` reads), and the sampled position (the hold's). :meth:`command`
    sets a new command between advances; the ``TrajectorySource`` plays its
    trajectory (Drake's ``UpdateTrajectory``: a copy of the Context's command, which
    the source cannot read from the Context).
    """

    def __init__(self, robot: RobotConfig):
        super().__init__()
        q0 = arms.named_pose(robot.initial_pose, robot)
        n = len(q0)
        builder = DiagramBuilder()
        self._source = builder.AddNamedSystem("trajectory", TrajectorySource(_played(JointCommand(q0))))
        self._hold = builder.AddNamedSystem(
            "sample",
            LinearSystem(
                np.zeros((n, n)),
                np.eye(n),
                np.eye(n),
                np.zeros((n, n)),
                time_period=1.0 / robot.command_rate_hz,
            ),
        )
        self._hold.configure_default_state(q0)
        self._memory = builder.AddNamedSystem("command", _CommandMemory(q0))
        builder.Connect(self._source.get_output_port(), self._hold.get_input_port())
        builder.ExportOutput(self._hold.get_output_port(), "position")
        builder.BuildInto(self)
        self.set_name(f"{robot.name}.commander")

    def position_output_port(self) -> OutputPort:
        """The ``position`` output: the sampled joint positions for the arm's servo."""
        return self.get_output_port(0)

    def command(self, context: Context, command: JointCommand) -> None:
        """The new command, from now on (the sampled position follows at the next sample)."""
        memory = self.GetMutableSubsystemContext(self._memory, context)
        memory.SetAbstractState(self._memory.index, command)
        self._source.UpdateTrajectory(_played(command))

    def hold(self, context: Context, q: np.ndarray) -> None:
        """Hold ``q`` from now, the sampled position too (not only from the next sample)."""
        q = np.array(q, dtype=float)
        self.command(context, JointCommand(q))
        self.GetMutableSubsystemContext(self._hold, context).SetDiscreteState(q)

    def current(self, context: Context) -> JointCommand:
        memory = self.GetSubsystemContext(self._memory, context)
        return memory.get_abstract_state(self._memory.index).get_value()

    def commanded_position(self, context: Context) -> np.ndarray:
        """The position the servo is being sent now."""
        return self.GetSubsystemContext(self._hold, context).get_discrete_state_vector().value().copy()


def _played(command: JointCommand) -> PiecewisePolynomial:
    """``command`` as the trajectory source plays it: on the simulator's time axis."""
    if command.trajectory is None:
        return PiecewisePolynomial(np.asarray(command.q, dtype=float).reshape(-1, 1))
    played = copy.copy(command.trajectory)
    played.shiftRight(command.t0)
    return played
