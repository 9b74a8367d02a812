"""The vacuum gripper's two ways of holding a part, and their wiring.

The attach rule (when a part is attached or released) is the base class
:class:`~omtp_drake.cell.suction.SuctionGripper`; frames as there (``C`` the
cup, ``P`` a part, ``W`` the world).

Two ways of holding the part (``SuctionConfig.backend``):

* ``"weld"`` (default): six rigid distance constraints of the plant, between
  three points of the cup and three points of the part (an octahedron, see
  :mod:`omtp_drake.cell.suction_constraints`). They are declared before
  ``Finalize()`` and rewritten at run time with the *current* distances, so
  the part is held exactly where it is. Constraint parameters live in the
  plant's Context and no system may write another system's Context, so the
  owner of the simulator calls :func:`sync_weld` between advances: the
  gripper's checks *decide* an attach, and the next :func:`sync_weld` (one
  runtime tick later at most) re-checks the touch, makes the constraints and
  only then reports ``attached`` (so a controller that lifts as soon as it
  sees ``attached`` never leaves the part behind). It also releases the
  constraints once the gripper has let go. Without :func:`sync_weld` calls a
  weld gripper never attaches (a warning is logged after 1 s). The part does not
  snap at the attach and drifts by micrometres in the cup (bench/README.md, "Measured").
* ``"force"``: a stiff 6-DOF spring-damper pulling the part toward
  ``X_WC * X_CP``, applied through the plant's ``applied_spatial_force``
  input. It lives entirely inside the diagram (no runtime help) and the hold
  starts at the attaching check itself, but it is compliant (a carried part
  drifts in the cup by millimetres, less at shorter plant steps: the limit of any
  explicit spring at a step), and it costs a Python evaluation every plant step
  while a part is held (bench/README.md, "Measured").

Typical use (station side)::

    constraints = declare_suction_constraints(plant, cup, any_part)   # weld, before Finalize
    plant.Finalize()
    gripper = add_suction_gripper(builder, plant, cup, parts, config, "suction1", constraints)
    connect_spatial_forces(builder, plant, [gripper])
    ...
    constraints.deactivate_all(plant, plant_context)    # every new Context
    while ...:
        simulator.AdvanceTo(t)
        sync_weld(gripper, plant, root_context)         # weld grippers only
"""

# No `from __future__ import annotations`, as in omtp_drake.cell.suction.

import logging
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce, SpatialVelocity
from pydrake.multibody.plant import (
    ExternallyAppliedSpatialForce_,
    ExternallyAppliedSpatialForceMultiplexer,
    MultibodyPlant,
)
from pydrake.multibody.tree import BodyIndex, RigidBody
from pydrake.systems.framework import Context, DiagramBuilder, InputPort, OutputPort

from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.suction import EVERY_STEP, CommandPolling, GripperMemory, GripperState, SuctionGripper
from omtp_drake.cell.suction_constraints import SuctionConstraints
from omtp_drake.errors import ConfigError, SimulationError, StateError
from omtp_drake.scenario.suction import SuctionConfig

_log = logging.getLogger(__name__)


ExternallyAppliedSpatialForce = ExternallyAppliedSpatialForce_[float]


@dataclass(frozen=True)
class _PartGains:
    """Force-backend gains of one part, capped to its stability limits."""

    k: float
    c: float
    kr: float
    cr: float
    p_PScm: np.ndarray  # centre of mass in the part frame


class WeldSuctionGripper(SuctionGripper):
    """A vacuum gripper that holds with the plant's rigid constraints.

    The checks *decide* an attach; the attach is *made* between advances by
    :func:`sync_weld` (constraint parameters live in the plant's Context, which
    no system may write), which re-checks the touch, writes the constraints at
    the part's current pose and only then reports ``attached``. Without
    :func:`sync_weld` a decided attach stays pending (a warning is logged after
    1 s). The hold does not snap the part and drifts by micrometres (see the module doc).

    The driver's API (used by :func:`sync_weld`): :attr:`constraints`,
    :meth:`pending_part`, :meth:`complete_attach`, :meth:`cancel_attach`,
    :meth:`remake_hold`.
    """

    def __init__(
        self,
        plant: MultibodyPlant,
        cup_body: RigidBody,
        part_bodies: Sequence[RigidBody],
        config: SuctionConfig,
        name: str,
        constraints: SuctionConstraints,
        polling: Optional[CommandPolling] = EVERY_STEP,
    ):
        super().__init__(plant, cup_body, part_bodies, config, name, polling)
        if int(constraints.cup) != self._cup:
            raise ConfigError(
                f"gripper {name!r}: the constraints belong to cup body "
                f"{int(constraints.cup)}, the gripper to {self._cup}"
            )
        self._constraints = constraints

    @property
    def constraints(self) -> SuctionConstraints:
        """The plant constraints this gripper holds with."""
        return self._constraints

    def pending_part(self, context: Context) -> str:
        """The part an attach was decided for, waiting for :func:`sync_weld`; "" when none."""
        memory = self._get_memory(context)
        return self._names[memory.pending_body] if memory.pending_body >= 0 else ""

    def complete_attach(self, context: Context, X_CP: RigidTransform) -> None:
        """The pending attach is made: the part is held at ``X_CP`` from now on."""
        memory = self._get_memory(context)
        if memory.pending_body < 0:
            raise SimulationError(f"{self.get_name()}: no attach is pending")
        name = self._names[memory.pending_body]
        t = context.get_time()
        _log.info("%s: attached %s at t = %.3f s", self.get_name(), name, t)
        held = GripperState(enabled=True, attached=True, part=name, X_CP=X_CP, since=t)
        self._set_memory(context, GripperMemory(held, last_check=memory.last_check))

    def cancel_attach(self, context: Context) -> None:
        """The pending attach is dropped; the count of good checks starts again."""
        memory = self._get_memory(context)
        if memory.pending_body >= 0:
            _log.info(
                "%s: attach of %s dropped at t = %.3f s (no longer touching)",
                self.get_name(),
                self._names[memory.pending_body],
                context.get_time(),
            )
        self._set_memory(context, GripperMemory(memory.state, last_check=memory.last_check))

    def remake_hold(self, context: Context, X_CP: RigidTransform) -> None:
        """The held part's captured pose after its constraints were re-made."""
        memory = self._get_memory(context)
        self._set_memory(context, replace(memory, state=replace(memory.state, X_CP=X_CP)))

    def _attach_decided(
        self, context: Context, idle: GripperState, streak: int, touching: int
    ) -> GripperMemory:
        _log.debug(
            "%s: attach of %s decided at t = %.3f s",
            self.get_name(),
            self._names[touching],
            context.get_time(),
        )
        return GripperMemory(idle, streak, touching, pending_body=touching, pending_since=context.get_time())

    def _while_pending(self, memory: GripperMemory, idle: GripperState, t: float) -> GripperMemory:
        waited = t - memory.pending_since
        if 1.0 <= waited < 1.0 + 1.0 / self._config.check_rate_hz:
            _log.warning(
                "%s: attach of %s pending for %.2f s: is sync_weld called between advances?",
                self.get_name(),
                self._names[memory.pending_body],
                waited,
            )
        return replace(memory, state=idle)


class ForceSuctionGripper(SuctionGripper):
    """A vacuum gripper that holds with a stiff 6-DOF spring-damper force.

    The hold starts at the attaching check itself and lives entirely inside the
    diagram, but it is compliant (0.3-0.8 mm drift carrying 0.2-1 kg at 1 m/s)
    and costs a Python evaluation every plant step while a part is held.

    .. pydrake_system::

        name: ForceSuctionGripper
        input_ports:
        - command
        - body_poses
        - contact_results
        - body_spatial_velocities
        output_ports:
        - state
        - spatial_forces

    Extra ports (besides :class:`~omtp_drake.cell.suction.SuctionGripper`'s):
      - input ``body_spatial_velocities`` (list of SpatialVelocity,
        :meth:`body_spatial_velocities_input_port`): the plant's body
        velocities, read while holding.
      - output ``spatial_forces`` (list of ExternallyAppliedSpatialForce,
        :meth:`spatial_forces_output_port`):
        while holding, the spring-damper wrench on the part (at its centre of
        mass) and, with ``apply_reaction``, the opposite wrench on the cup at
        the same point; empty otherwise. Feed it to the plant with
        :func:`connect_spatial_forces`.
    """

    def _declare_hold(self, plant: MultibodyPlant, part_bodies: Sequence[RigidBody]) -> None:
        """The spring-damper gains of every part, the velocities input and the forces output."""
        self._gains = {int(b.index()): _gains_for(b, self._config, plant.time_step()) for b in part_bodies}
        self._velocities = self.DeclareAbstractInputPort(
            "body_spatial_velocities", AbstractValue.Make([SpatialVelocity()])
        )
        self._forces_port = self.DeclareAbstractOutputPort(
            "spatial_forces",
            lambda: AbstractValue.Make([ExternallyAppliedSpatialForce()]),
            weak_method(self._calc_forces),  # C++ holds it (see cell.lifetime)
            prerequisites_of_calc={
                self.abstract_state_ticket(self._memory),
                self.input_port_ticket(self._poses.get_index()),
                self.input_port_ticket(self._velocities.get_index()),
            },
        )

    def body_spatial_velocities_input_port(self) -> InputPort:
        """The ``body_spatial_velocities`` input: the plant's body velocities."""
        return self._velocities

    def spatial_forces_output_port(self) -> OutputPort:
        """The ``spatial_forces`` output: the hold's wrenches, for the plant."""
        return self._forces_port

    def _attach_decided(
        self, context: Context, idle: GripperState, streak: int, touching: int
    ) -> GripperMemory:
        X_WB = self._poses.Eval(context)
        X_CP = X_WB[self._cup].InvertAndCompose(X_WB[touching])
        t = context.get_time()
        _log.info("%s: attached %s at t = %.3f s", self.get_name(), self._names[touching], t)
        return GripperMemory(
            GripperState(enabled=True, attached=True, part=self._names[touching], X_CP=X_CP, since=t)
        )

    def _calc_forces(self, context: Context, output: AbstractValue) -> None:
        state = self._get_memory(context).state
        if not state.attached or state.X_CP is None:
            output.set_value([])
            return
        part = self._bodies[state.part]
        g = self._gains[part]
        # Only the two bodies' poses and velocities, as plain arrays (pydrake
        # accessors and np.cross are slow at this size).
        poses = self._poses.Eval(context)
        velocities = self._velocities.Eval(context)
        M_WC, M_WP = poses[self._cup].GetAsMatrix34(), poses[part].GetAsMatrix34()
        V_WC, V_WP = velocities[self._cup].get_coeffs(), velocities[part].get_coeffs()
        M_CP = state.X_CP.GetAsMatrix34()
        R_WC, p_WC, R_WP, p_WP = M_WC[:, :3], M_WC[:, 3], M_WP[:, :3], M_WP[:, 3]
        # Part's centre of mass Scm now, and where the cup wants it (Scm_d).
        r_PScm_W = R_WP @ g.p_PScm
        r_CScmd_W = R_WC @ (M_CP[:, 3] + M_CP[:, :3] @ g.p_PScm)
        p_err = (p_WC + r_CScmd_W) - (p_WP + r_PScm_W)
        # Velocity of Scm minus that of the cup-fixed point at Scm_d.
        v_rel = (V_WP[3:] + _cross(V_WP[:3], r_PScm_W)) - (V_WC[3:] + _cross(V_WC[:3], r_CScmd_W))
        f = g.k * p_err - g.c * v_rel
        # Rotation error R_WPd R_WP^T as a rotation vector, small-angle form (sin(angle) axis).
        R_err = (R_WC @ M_CP[:, :3]) @ R_WP.T
        theta = 0.5 * np.array(
            [R_err[2, 1] - R_err[1, 2], R_err[0, 2] - R_err[2, 0], R_err[1, 0] - R_err[0, 1]]
        )
        tau = g.kr * theta - g.cr * (V_WP[:3] - V_WC[:3])
        on_part = ExternallyAppliedSpatialForce()
        on_part.body_index = BodyIndex(part)
        on_part.p_BoBq_B = g.p_PScm
        on_part.F_Bq_W = SpatialForce(tau, f)
        if not self._config.apply_reaction:
            output.set_value([on_part])
            return
        on_cup = ExternallyAppliedSpatialForce()
        on_cup.body_index = BodyIndex(self._cup)
        on_cup.p_BoBq_B = R_WC.T @ (p_WP + r_PScm_W - p_WC)
        on_cup.F_Bq_W = SpatialForce(-tau, -f)
        output.set_value([on_part, on_cup])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for 3-vectors (np.cross costs ~20x more at this size)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _gains_for(body: RigidBody, config: SuctionConfig, h: float) -> _PartGains:
    """The force gains for ``body``, capped at its deadbeat limits for step ``h``."""
    M_PPo_P = body.default_spatial_inertia()
    m = M_PPo_P.get_mass()
    p_PScm = np.array(M_PPo_P.get_com(), dtype=float)
    I_PScm_P = M_PPo_P.Shift(p_PScm).CalcRotationalInertia()
    inertia = float(np.min(np.linalg.eigvalsh(I_PScm_P.CopyToFullMatrix3())))
    k, c = config.stiffness, config.damping
    kr, cr = config.angular_stiffness, config.angular_damping
    if h > 0 and m > 0:
        k, c = min(k, m / h**2), min(c, m / h)
    if h > 0 and inertia > 0:
        kr, cr = min(kr, inertia / h**2), min(cr, inertia / h)
    return _PartGains(k, c, kr, cr, p_PScm)


def sync_weld(gripper: WeldSuctionGripper, plant: MultibodyPlant, root_context: Context) -> None:
    """Makes a weld gripper's constraints follow its state; call between advances.

    * An attach decided by the gripper's checks is made here: if the part
      still touches the cup (same rule as a check), the constraints hold it at
      its current pose in the cup and the gripper's state becomes attached
      (``X_CP`` that pose, ``since`` now); if not, the decision is dropped and
      the count of good checks starts again.
    * A state that says attached while the constraints do not hold the part
      (e.g. a fresh plant Context) is re-made at the current pose.
    * A state that says nothing is attached releases the constraints.

    Writes nothing when already in sync.
    """
    if not isinstance(gripper, WeldSuctionGripper):
        raise ConfigError(
            f"sync_weld needs a weld gripper; {gripper.get_name()!r} has backend {gripper.config.backend!r}"
        )
    constraints = gripper.constraints
    gripper_context = gripper.GetMyMutableContextFromRoot(root_context)
    plant_context = plant.GetMyMutableContextFromRoot(root_context)
    state = gripper.get_state(gripper_context)
    held = constraints.held_body(plant, plant_context)
    if state.attached:
        index = gripper.part_body_index(state.part)
        if held is None or int(held) != int(index):
            gripper.remake_hold(
                gripper_context, constraints.attach(plant, plant_context, plant.get_body(index))
            )
        return
    if held is not None:
        constraints.release(plant, plant_context)
    pending = gripper.pending_part(gripper_context)
    if not pending:
        return
    if gripper.touching_part(gripper_context) != pending:
        gripper.cancel_attach(gripper_context)
        return
    X_CP = constraints.attach(plant, plant_context, plant.get_body(gripper.part_body_index(pending)))
    gripper.complete_attach(gripper_context, X_CP)


def add_suction_gripper(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    cup_body: RigidBody,
    part_bodies: Sequence[RigidBody],
    config: SuctionConfig,
    name: str,
    constraints: Optional[SuctionConstraints] = None,
    polling: Optional[CommandPolling] = EVERY_STEP,
) -> SuctionGripper:
    """Adds the vacuum gripper of ``config.backend`` named ``name`` and connects it to the plant.

    ``polling``: when it applies its rule by itself (:class:`~omtp_drake.cell.suction.CommandPolling`;
    None: only when its owner runs its forced event).

    ``weld`` needs the ``constraints`` declared for this cup before the plant was finalized
    (:func:`~omtp_drake.cell.suction_constraints.declare_suction_constraints`); ``force`` needs none.
    Connects the plant's outputs the gripper reads; ``command`` is left to the
    caller, and so are the force outputs (see :func:`connect_spatial_forces`).
    """
    config.validate()
    gripper: SuctionGripper
    if config.backend == "weld":
        if constraints is None:
            raise ConfigError(
                f"gripper {name!r}: the weld backend needs its constraints "
                "(declare_suction_constraints before plant.Finalize())"
            )
        gripper = WeldSuctionGripper(plant, cup_body, part_bodies, config, name, constraints, polling)
    else:
        gripper = ForceSuctionGripper(plant, cup_body, part_bodies, config, name, polling)
    builder.AddNamedSystem(name, gripper)
    if isinstance(gripper, ForceSuctionGripper):
        builder.Connect(
            plant.get_body_spatial_velocities_output_port(), gripper.body_spatial_velocities_input_port()
        )
    builder.Connect(plant.get_body_poses_output_port(), gripper.body_poses_input_port())
    builder.Connect(plant.get_contact_results_output_port(), gripper.contact_results_input_port())
    return gripper


def connect_spatial_forces(
    builder: DiagramBuilder, plant: MultibodyPlant, grippers: Sequence[SuctionGripper]
) -> None:
    """Feeds the force grippers' ``spatial_forces`` to the plant.

    The plant has a single ``applied_spatial_force`` input: one force gripper
    is connected directly, several through an
    ``ExternallyAppliedSpatialForceMultiplexer``. Weld grippers have no force
    output; with no force gripper nothing is connected.
    """
    sources = [g for g in grippers if isinstance(g, ForceSuctionGripper)]
    if not sources:
        return
    port = plant.get_applied_spatial_force_input_port()
    if builder.IsConnectedOrExported(port):
        raise StateError(
            "the plant's applied_spatial_force input is already connected; "
            "connect_spatial_forces must be its only source"
        )
    if len(sources) == 1:
        builder.Connect(sources[0].spatial_forces_output_port(), port)
        return
    mux = builder.AddNamedSystem("suction_forces", ExternallyAppliedSpatialForceMultiplexer(len(sources)))
    for i, gripper in enumerate(sources):
        builder.Connect(gripper.spatial_forces_output_port(), mux.get_input_port(i))
    builder.Connect(mux.get_output_port(), port)
