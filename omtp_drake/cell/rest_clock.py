"""How long each part has been still: what lets a resting part fall asleep.

A part at rest costs the contact solver and the geometry queries as much as a
moving one, so a run slows down as parts pile up in a bin (figures:
bench/README.md, "Measured"). A sleeping
part has its floating joint locked, so the solver drops its degrees of freedom,
and its pairs with what never moves filtered (physics engines do the same:
Bullet's deactivation). Sleeping is a world edit, made between advances by
:class:`omtp_drake.sim.part_sleep.PartSleep`; this module holds what it decides
with: :class:`RestClock`, the system whose state says since when each part has
been still, and the station's record of which parts sleep (a locked joint away
from the part's parking slot, :meth:`omtp_drake.cell.parts.PartStates.is_asleep`).
"""

from __future__ import annotations

import math

import numpy as np
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.framework import (
    BasicVector,
    Context,
    DiagramBuilder,
    DiscreteValues,
    InputPort,
    LeafSystem,
    OutputPort,
)

from omtp_drake.cell.lifetime import weak_method
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario import SleepConfig


class RestClock(LeafSystem):
    """For each part, the time since which it has been still.

    .. pydrake_system::

        name: RestClock
        input_ports:
        - plant_state
        output_ports:
        - still_since

    ``still_since[k]`` (s) is the first sample time of the unbroken run of
    samples, up to the latest, at which part ``k`` (in the order of ``parts``)
    moved slower than ``config.linear_speed`` and ``config.angular_speed``; inf
    while it moves. Sampled every ``1 / config.check_rate_hz`` s. A locked part
    (parked or asleep) has zero velocity, so it counts as still.

    With ``periodic`` (the default) the clock samples itself. Without it, its owner
    (:class:`omtp_drake.sim.part_sleep.PartSleep`, the driver's) takes each sample
    (:meth:`sample`) at the same times, and only while some part is
    free: while every part is locked, a sample could only say "still since the first
    of these samples", so the owner records that time once (:meth:`all_locked_at`)
    and the clock counts it in (``still_since`` is the same as if it had sampled).
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        parts: dict[str, ModelInstanceIndex],
        config: SleepConfig,
        periodic: bool = True,
    ):
        super().__init__()
        config.validate()
        self._names = list(parts)
        starts = []
        for name in self._names:
            body = plant.GetBodyByName(name, parts[name])
            if not body.is_floating_base_body():
                raise ConfigError(f"rest clock: part {name!r} must be a free body")
            starts.append(plant.num_positions() + body.floating_velocities_start_in_v())
        # Each part's velocities [w; v] (angular, then translational): their indices in
        # the plant's state [q; v].
        self._velocity = [tuple(range(k, k + 6)) for k in starts]
        self._limits_squared = (config.angular_speed**2, config.linear_speed**2)
        self._plant_state = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self._state = self.DeclareDiscreteState(np.full(len(self._names), math.inf))
        #: The first sample time since which every part has been locked (inf: not so).
        self._all_locked = self.DeclareDiscreteState(np.array([math.inf]))
        period = 1.0 / config.check_rate_hz
        if periodic:
            self.DeclarePeriodicDiscreteUpdateEvent(period, 0.0, self._update)
        self._still_since = self.DeclareVectorOutputPort(
            "still_since",
            len(self._names),
            weak_method(self._calc_still_since),  # C++ holds it (see cell.lifetime)
            prerequisites_of_calc={self.all_state_ticket()},
        )

    @staticmethod
    def AddToDiagram(
        builder: DiagramBuilder,
        plant: MultibodyPlant,
        parts: dict[str, ModelInstanceIndex],
        config: SleepConfig,
        periodic: bool = True,
    ) -> RestClock:
        """Adds a RestClock of ``parts`` to ``builder`` and connects it to ``plant``."""
        clock = builder.AddSystem(RestClock(plant, parts, config, periodic))
        clock.set_name("rest_clock")
        builder.Connect(plant.get_state_output_port(), clock.plant_state_input_port())
        return clock

    def plant_state_input_port(self) -> InputPort:
        return self._plant_state

    def still_since_output_port(self) -> OutputPort:
        return self._still_since

    @property
    def part_names(self) -> list[str]:
        """The parts, in the order of :meth:`still_since_values`."""
        return list(self._names)

    def still_since(self, context: Context) -> dict[str, float]:
        """part -> the time since which it has been still (inf: moving)."""
        return dict(zip(self._names, self.still_since_values(context)))

    def still_since_values(self, context: Context) -> np.ndarray:
        """The times since which the parts have been still (inf: moving), in the order
        of :attr:`part_names` (a copy)."""
        since = context.get_discrete_state(self._state).CopyToVector()
        all_locked = context.get_discrete_state(self._all_locked)[0]
        return since if all_locked == math.inf else np.minimum(since, all_locked)

    def _calc_still_since(self, context: Context, output: BasicVector) -> None:
        output.SetFromVector(self.still_since_values(context))

    def sample(self, context: Context) -> None:
        """Takes a sample now (a clock built without ``periodic``; its owner, a world edit
        of the driver, calls this at the sample times while some part is free). Written
        straight into the clock's state, as the owner's other edits are (no event to
        dispatch): the same values as its periodic event's."""
        context.get_mutable_discrete_state(self._state).SetFromVector(self._sampled(context))
        if context.get_discrete_state(self._all_locked)[0] != math.inf:
            context.get_mutable_discrete_state(self._all_locked).SetAtIndex(0, math.inf)

    def all_locked_at(self, context: Context, t: float) -> None:
        """Every part is locked at the sample time ``t`` and will be until the next sample
        taken: recorded once, instead of samples that would each say still since the first."""
        state = context.get_mutable_discrete_state(self._all_locked)
        if state[0] == math.inf:
            state.SetAtIndex(0, t)

    def restart(self, context: Context, name: str, t: float) -> None:
        """Part ``name`` counts as still only from ``t`` on (a part just woken)."""
        if name not in self._names:
            raise UnknownNameError("part", name, self._names)
        self._count_locked_time(context)
        state = context.get_mutable_discrete_state(self._state)
        state.SetAtIndex(self._names.index(name), t)

    def _count_locked_time(self, context: Context) -> None:
        """Folds the recorded all-locked time into each part's value."""
        if context.get_discrete_state(self._all_locked)[0] != math.inf:
            context.get_mutable_discrete_state(self._state).SetFromVector(self.still_since_values(context))
            context.get_mutable_discrete_state(self._all_locked).SetAtIndex(0, math.inf)

    def _update(self, context: Context, discrete_state: DiscreteValues) -> None:
        discrete_state.set_value(self._state, np.array(self._sampled(context)))
        discrete_state.set_value(self._all_locked, np.array([math.inf]))

    def _sampled(self, context: Context) -> list[float]:
        """The parts' values after a sample now (the all-locked time counted in)."""
        # In plain floats: a dozen parts cost less than numpy's small-array calls
        # between plant steps (bench/README.md).
        x = self._plant_state.Eval(context).tolist()
        t = context.get_time()
        w2, v2 = self._limits_squared
        since = context.get_discrete_state(self._state).value().tolist()
        all_locked = context.get_discrete_state(self._all_locked)[0]
        if all_locked != math.inf:  # the samples not taken while every part was locked
            since = [min(s, all_locked) for s in since]
        now = []
        for (a, b, c, d, e, f), s in zip(self._velocity, since):
            still = (
                x[a] * x[a] + x[b] * x[b] + x[c] * x[c] < w2 and x[d] * x[d] + x[e] * x[e] + x[f] * x[f] < v2
            )
            now.append(min(s, t) if still else math.inf)
        return now
