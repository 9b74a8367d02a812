"""The vacuum (suction) gripper: enable / disable, attach on contact, release on disable.

Behaviour (the course's gripper plugin, ``VacuumGripperPlugin``, on simulated
time): the plugin looks at its command at every physics update; here the gripper
applies its rule at the plant step at or after its command changed. While enabled
it checks for contact at once (that first step) and then every ``1 / check_rate_hz``
(0.1 s, the plugin's ``updateRate``) after its last check. A movable part touching the suction cup with
the contact normal within ``max_angle_deg`` (18 deg) of the tool axis on
``consecutive_checks`` (2) consecutive checks is attached **at its current pose
relative to the cup** (no snapping): 0.1 s after enabling a gripper pressed
onto a part. A disable releases at the next step (it then falls freely from
where it was); unlike the course, a hold is also lost when it is physically
lost (the part was pulled more than ``max_hold_distance`` away from its
captured pose).

Frames (monogram notation, ``X_AB`` is the pose of frame B in frame A):

* ``W``: the world frame.
* ``C``: the cup body ``<gripper>_cup``. Its origin is the physical cup face
  (tool0 + 0.0775 m, same place as the frame ``<gripper>_tip``) and +Cz points
  out of the tool, toward the part being picked. Its collision geometry
  ``suction_cup`` (a cylinder, r = 0.02 m) lies behind the face (-Cz).
* ``P``: a part's body frame (the centre of a cube part).
* ``X_CP``: the part's pose in the cup, captured when it is attached.

When the rule runs (:class:`CommandPolling`): a gripper used alone polls its command
at every plant step (:data:`EVERY_STEP`); in the station, a gripper whose command a
controller of the diagram writes polls it at that controller's rate, one plant step
after each of its updates, and a gripper commanded by services (a script, ROS) does
not poll at all: its owner runs the rule (a forced event) at the step
the command changes and when a check is due, so an idle gripper costs nothing
(:class:`omtp_drake.sim.gripper_events.GripperEvents`).

The attach rule and the state live here (:class:`SuctionGripper`,
:class:`GripperState`); the two ways of holding a part (``"weld"``: rigid
constraints of the plant; ``"force"``: a spring-damper inside the diagram),
the factory :func:`~omtp_drake.cell.suction_holds.add_suction_gripper` and
:func:`~omtp_drake.cell.suction_holds.sync_weld` live in
:mod:`omtp_drake.cell.suction_holds`.
"""
# No `from __future__ import annotations`: SuctionConfig is part of the
# scenario YAML schema and Drake's typed loader reads field types at run time.

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.plant import (
    ContactResults,
    MultibodyPlant,
)
from pydrake.multibody.tree import BodyIndex, RigidBody
from pydrake.systems.framework import Context, EventStatus, InputPort, LeafSystem, OutputPort, State

from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.suction_touch import contact_points, part_body_indices, touching_part
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario.suction import SuctionConfig

_log = logging.getLogger(__name__)

#: The gripper's public names (``contact_points`` lives in
#: :mod:`omtp_drake.cell.suction_touch` and is named here too, for its users).
__all__ = [
    "EVERY_STEP",
    "CommandPolling",
    "GripperMemory",
    "GripperState",
    "SuctionGripper",
    "contact_points",
    "memory_of",
    "next_check_after",
]


@dataclass(frozen=True)
class GripperState:
    """What a vacuum gripper reports (its ``state`` output).

    Attributes:
        enabled: the command as sampled at the last check.
        attached: a part is held. Force backend: from the attaching check on.
            Weld backend: from the :func:`~omtp_drake.cell.suction_holds.sync_weld` that made the constraints
            on (the check only decides; a controller that lifts as soon as it
            sees ``attached`` never leaves the part behind).
        part: the held part's body name; "" when none.
        X_CP: the held part's pose in the cup frame, captured when the hold
            began; None when none.
        since: simulated time at which the hold began; nan when none.
        last_release: why the last part was let go: "" (none yet),
            ``"disabled"``, ``"hold lost"`` or ``"fault"`` (see fail_vacuum).
            Cleared at the next attach.
    """

    enabled: bool
    attached: bool
    part: str
    X_CP: Optional[RigidTransform]
    since: float
    last_release: str = ""


@dataclass(frozen=True)
class GripperMemory:
    """The gripper's abstract state: what it reports plus its count of good checks
    (its holds in :mod:`omtp_drake.cell.suction_holds` write it too)."""

    state: GripperState
    #: Number of consecutive good checks of ``streak_body``.
    streak: int = 0
    #: Body index of the part seen on the last good check (-1: none).
    streak_body: int = -1
    #: Weld backend: the part the checks decided to attach, waiting for
    #: :func:`~omtp_drake.cell.suction_holds.sync_weld` (-1: none), and when that was decided.
    pending_body: int = -1
    pending_since: float = math.nan
    #: Simulated time of the last contact check (-inf: none yet). The next one is
    #: due ``1 / check_rate_hz`` later, or at once after a disable of that long.
    last_check: float = -math.inf

    def __deepcopy__(self, memo: dict) -> "GripperMemory":
        return self  # immutable: Drake clones abstract state at every check


_IDLE = GripperState(enabled=False, attached=False, part="", X_CP=None, since=math.nan)

#: Times closer than this (s) are the same time; a poll this much before a check is
#: due makes the check.
_EPS = 1e-9
CHECK_TOLERANCE = _EPS


@dataclass(frozen=True)
class CommandPolling:
    """When a gripper applies its rule by itself: a periodic event of the diagram
    every ``period`` s from ``offset``. ``period`` 0 means every plant step from
    t = 0 (:data:`EVERY_STEP`: a gripper used alone, its command fixed by whoever runs
    the simulator). A check falls on a poll, so ``1 / check_rate_hz`` should be a
    multiple of ``period`` (then checks are 0.1 s apart, as the plugin's)."""

    period: float = 0.0
    offset: float = 0.0

    def __post_init__(self) -> None:
        if not (self.period >= 0 and self.offset >= 0):
            raise ConfigError(f"gripper polling period and offset must be >= 0, got {self}")

    def at_step(self, step: float) -> "CommandPolling":
        """This polling, with the plant's ``step`` for a ``period`` of 0 (every step)."""
        return self if self.period else CommandPolling(step, self.offset)


#: Poll the command at every plant step (the plugin at every physics update).
EVERY_STEP = CommandPolling()


class SuctionGripper(LeafSystem):
    """A vacuum gripper on a cup body: the course's attach rule, at the course plugin's check times.

    This base class decides *when* a part is attached or released; its two
    subclasses decide *how* it is held: :class:`~omtp_drake.cell.suction_holds.WeldSuctionGripper` (rigid
    constraints of the plant, made between advances by :func:`~omtp_drake.cell.suction_holds.sync_weld`) and
    :class:`~omtp_drake.cell.suction_holds.ForceSuctionGripper` (a spring-damper force inside the diagram).
    Build one with :func:`~omtp_drake.cell.suction_holds.add_suction_gripper`, which picks the class from
    ``SuctionConfig.backend``.

    .. pydrake_system::

        name: SuctionGripper
        input_ports:
        - command
        - body_poses
        - contact_results
        output_ports:
        - state

    Input ports:
      - ``command`` (vector [1], :meth:`command_input_port`): > 0.5 enables
        the gripper.
      - ``body_poses`` (list of RigidTransform, :meth:`body_poses_input_port`):
        the plant's body poses X_WB.
      - ``contact_results`` (ContactResults, :meth:`contact_results_input_port`):
        the plant's contact results; point-pair contacts are used (the station
        uses point contact).

    Output ports:
      - ``state`` (:class:`GripperState`, :meth:`state_output_port`): depends
        on the state only.

    State (abstract; the rule, at the polls of :attr:`polling` or as a forced event
    the owner runs): the :class:`GripperState`, the count of good checks and the time
    of the last (a check runs at a poll of an enabled gripper ``1 / check_rate_hz``
    after the last); discrete: the end of an injected vacuum failure.

    Frames: C is the cup body ``<gripper>_cup`` (origin at the cup face,
    like the frame ``<gripper>_tip``, tool0 + 0.0775 m; +Cz out of the tool;
    the course's planning frame ``<gripper>_suction_cup`` is tool0 + 0.01 m);
    P a candidate part's body frame; W the world. A touch is good when the
    contact normal pointing from the part into the cup is within
    ``max_angle_deg`` of -Cz (i.e. the part is in front of the cup face).
    Contact results of a plant with sampled output ports lag one step (and are
    empty at t = 0); the station's unsampled ports are current.

    The system keeps no reference to the plant: it reads body indices (and, for
    the force hold, the parts' inertias and the plant's time step) at
    construction. Candidate parts must be movable (not anchored).
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        cup_body: RigidBody,
        part_bodies: Sequence[RigidBody],
        config: SuctionConfig,
        name: str = "suction",
        polling: Optional[CommandPolling] = EVERY_STEP,
    ):
        super().__init__()
        if not plant.is_finalized():
            raise ConfigError(f"gripper {name!r}: the plant must be finalized first")
        self.set_name(name)
        self._config = config
        self._cup = int(cup_body.index())
        self._bodies = part_body_indices(plant, self._cup, part_bodies, name)
        self._names = {index: n for n, index in self._bodies.items()}
        self._cos_max = math.cos(math.radians(config.max_angle_deg))
        self._check_period = 1.0 / config.check_rate_hz
        # The plugin's physics update: a plant step (continuous plant: Gazebo's 1 ms).
        self._step = min(plant.time_step() or 1e-3, self._check_period)
        self._polling = polling = polling and polling.at_step(self._step)
        self._command = self.DeclareVectorInputPort("command", 1)
        self._poses = self.DeclareAbstractInputPort("body_poses", AbstractValue.Make([RigidTransform()]))
        self._contacts = self.DeclareAbstractInputPort(
            "contact_results", AbstractValue.Make(ContactResults())
        )
        self._memory = self.DeclareAbstractState(AbstractValue.Make(GripperMemory(_IDLE)))
        # Fault injection: the vacuum fails (commands are ignored, nothing is held)
        # until this time; see fail_vacuum().
        self._fault = self.DeclareDiscreteState(np.array([-math.inf]))
        if polling is not None:
            self.DeclarePeriodicUnrestrictedUpdateEvent(polling.period, polling.offset, self._check)
        self.DeclareForcedUnrestrictedUpdateEvent(self._check)  # the owner's runs of the rule
        self._state_port = self.DeclareAbstractOutputPort(
            "state",
            lambda: AbstractValue.Make(_IDLE),
            weak_method(self._calc_state),  # C++ holds it (see cell.lifetime)
            prerequisites_of_calc={self.abstract_state_ticket(self._memory)},
        )
        self._declare_hold(plant, part_bodies)

    def _declare_hold(self, plant: MultibodyPlant, part_bodies: Sequence[RigidBody]) -> None:
        """The ports and facts of a subclass's way to hold, at the end of construction."""

    # ------------------------------------------------------------------ ports

    def command_input_port(self) -> InputPort:
        """The ``command`` input: > 0.5 enables the gripper."""
        return self._command

    def body_poses_input_port(self) -> InputPort:
        """The ``body_poses`` input: the plant's body poses X_WB."""
        return self._poses

    def contact_results_input_port(self) -> InputPort:
        """The ``contact_results`` input: the plant's contact results."""
        return self._contacts

    def state_output_port(self) -> OutputPort:
        """The ``state`` output: the :class:`GripperState`."""
        return self._state_port

    # ------------------------------------------------------------------ queries

    @property
    def config(self) -> SuctionConfig:
        return self._config

    @property
    def polling(self) -> Optional[CommandPolling]:
        """When it applies its rule by itself (None: when its owner runs its forced event)."""
        return self._polling

    def next_check(self, context: Context) -> float:
        """When an enabled gripper's next contact check is due (-inf: none yet, at once)."""
        return next_check_after(self, self._get_memory(context))

    @property
    def cup_body_index(self) -> BodyIndex:
        return BodyIndex(self._cup)

    def part_names(self) -> list[str]:
        """Names of the candidate part bodies."""
        return list(self._bodies)

    def part_body_index(self, name: str) -> BodyIndex:
        """The body index of candidate part ``name``."""
        if name not in self._bodies:
            raise UnknownNameError("suction part", name, self._bodies, closest=True)
        return BodyIndex(self._bodies[name])

    def get_state(self, context: Context) -> GripperState:
        """The gripper's state in its own ``context``."""
        return self._get_memory(context).state

    def touching_part(self, context: Context) -> str:
        """The candidate part touching the cup well now (the deepest), by the same
        rule as a check; "" when none."""
        index = self._touching_part(context)
        return self._names[index] if index >= 0 else ""

    def fail_vacuum(self, context: Context, until: float) -> None:
        """Fault injection: the vacuum fails until ``until`` (simulated time): a held
        part is dropped at the next poll and nothing attaches, whatever the command."""
        context.SetDiscreteState(self._fault, np.array([float(until)]))

    def fault_until(self, context: Context) -> float:
        """End of the injected vacuum failure (-inf: none injected)."""
        return float(context.get_discrete_state(self._fault)[0])

    # ------------------------------------------------------------------ the rule

    def _calc_state(self, context: Context, output: AbstractValue) -> None:
        output.set_value(self._get_memory(context).state)

    def _check(self, context: Context, state: State) -> EventStatus:
        memory = self._get_memory(context)
        new = self._next(context, memory)
        if new is memory:  # most polls (an idle gripper, between checks) change nothing
            return EventStatus.DidNothing()
        state.get_mutable_abstract_state(self._memory).set_value(new)
        return EventStatus.Succeeded()

    def _next(self, context: Context, memory: GripperMemory) -> GripperMemory:
        """The attach / release rule: the memory after one poll."""
        old = memory.state
        t = context.get_time()
        enabled = bool(self._command.Eval(context)[0] > 0.5)
        if t < self.fault_until(context):
            if old.attached:
                _log.warning("%s: vacuum failure: dropped %s at t = %.3f s", self.get_name(), old.part, t)
            last_release = "fault" if old.attached else old.last_release
            idle = replace(_IDLE, enabled=enabled, last_release=last_release)
            return GripperMemory(idle, last_check=memory.last_check)
        if not enabled:
            if old.attached:
                _log.info("%s: released %s at t = %.3f s (disabled)", self.get_name(), old.part, t)
                return GripperMemory(replace(_IDLE, last_release="disabled"), last_check=memory.last_check)
            if not old.enabled and memory.streak_body < 0 and memory.pending_body < 0:
                return memory  # idle already (an unused arm's gripper, most polls)
            return GripperMemory(replace(_IDLE, last_release=old.last_release), last_check=memory.last_check)
        if t - memory.last_check < self._check_period - CHECK_TOLERANCE:
            return memory  # enabled, between two checks
        return replace(self._check_contact(context, memory, t), last_check=t)

    def _check_contact(self, context: Context, memory: GripperMemory, t: float) -> GripperMemory:
        """One contact check of an enabled gripper (the hold, or the count toward an attach)."""
        old = memory.state
        if old.attached and old.X_CP is not None:
            X_WB = self._poses.Eval(context)
            X_CP_now = X_WB[self._cup].InvertAndCompose(X_WB[self._bodies[old.part]])
            offset = float(np.linalg.norm(X_CP_now.translation() - old.X_CP.translation()))
            if offset > self._config.max_hold_distance:
                _log.warning(
                    "%s: hold of %s lost at t = %.3f s (%.4f m from its captured pose, limit %.4f m)",
                    self.get_name(),
                    old.part,
                    t,
                    offset,
                    self._config.max_hold_distance,
                )
                return GripperMemory(replace(_IDLE, enabled=True, last_release="hold lost"))
            return GripperMemory(replace(old, enabled=True))
        idle = replace(_IDLE, enabled=True, last_release=old.last_release)
        if memory.pending_body >= 0:
            return self._while_pending(memory, idle, t)
        touching = self._touching_part(context)
        if touching < 0:
            return GripperMemory(idle)
        streak = memory.streak + 1 if touching == memory.streak_body else 1
        if streak < self._config.consecutive_checks:
            return GripperMemory(idle, streak, touching)
        return self._attach_decided(context, idle, streak, touching)

    def _attach_decided(
        self, context: Context, idle: GripperState, streak: int, touching: int
    ) -> GripperMemory:
        """The memory once the rule has decided to attach body ``touching``."""
        raise NotImplementedError  # each hold decides (a subclass always overrides this)

    def _while_pending(self, memory: GripperMemory, idle: GripperState, t: float) -> GripperMemory:
        return replace(memory, state=idle)

    def _touching_part(self, context: Context) -> int:
        """Body index of the candidate part touching the cup well (deepest), or -1."""
        # The cup's axis first, as a copy, and no other Eval while the contact results
        # are read: ``contacts`` is a view of the plant's cache. With the pose Eval
        # among those reads, a normal was read as if the part were not under the cup
        # and sync_weld dropped a good attach (run counts: bench/README.md, "Measured").
        z_WC = np.array(self._poses.Eval(context)[self._cup].rotation().col(2))
        return touching_part(self._contacts.Eval(context), self._cup, self._names, z_WC, self._cos_max)

    def _get_memory(self, context: Context) -> GripperMemory:
        return context.get_abstract_state(self._memory).get_value()

    def _set_memory(self, context: Context, memory: GripperMemory) -> None:
        context.SetAbstractState(self._memory, memory)


def memory_of(gripper: SuctionGripper, context: Context) -> GripperMemory:
    """``gripper``'s abstract state in its own ``context`` (its state, its count of good
    checks, the time of its last check): one read where several are needed."""
    return gripper._get_memory(context)


def next_check_after(gripper: SuctionGripper, memory: GripperMemory) -> float:
    """:meth:`SuctionGripper.next_check` for ``gripper``'s ``memory`` (:func:`memory_of`)."""
    return memory.last_check + gripper._check_period
