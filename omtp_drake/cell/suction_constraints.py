"""The weld hold's rigid constraints: six distance constraints between the cup and a part.

:func:`declare_suction_constraints` declares them before ``Finalize()`` (on a
placeholder part); :class:`SuctionConstraints` rewrites them at run time to hold
a part where it is, and lets it go. The six constraints are the side edges of a
regular octahedron (:func:`octahedron`), which fix the relative pose. Frames as
in :mod:`omtp_drake.cell.suction` (``C`` the cup, ``P`` a part, ``W`` the world).
"""

# No `from __future__ import annotations`, as in omtp_drake.cell.suction.

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.plant import DiscreteContactSolver, DistanceConstraintParams, MultibodyPlant
from pydrake.multibody.tree import BodyIndex, MultibodyConstraintId, RigidBody
from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError, StateError

#: Circumradius of the cup's and the part's triangles of constraint points [m].
_TRIANGLE_RADIUS = 0.05
#: Distance along +Cz between the two triangles (regular octahedron) [m].
_TRIANGLE_GAP = _TRIANGLE_RADIUS * math.sqrt(3.0) * math.sqrt(2.0 / 3.0)


def octahedron() -> tuple[np.ndarray, np.ndarray, list[tuple[int, int]]]:
    """Points a_i (in C), b_j (in C, on the part side) and the six (i, j) pairs.

    Two equilateral triangles of circumradius R in planes normal to Cz, one at
    the cup face and one R sqrt(2) further along +Cz, turned 60 deg from each
    other, form a regular octahedron; its six "side" edges join each a_i to
    b_i and b_(i+1). With the triangles rigid (they belong to the bodies), the
    octahedron is rigid, so the six lengths fix the relative pose.
    """
    angles_a = np.radians([90.0, 210.0, 330.0])
    angles_b = angles_a + np.radians(60.0)
    R = _TRIANGLE_RADIUS
    a = np.stack([R * np.cos(angles_a), R * np.sin(angles_a), np.zeros(3)], axis=1)
    b = np.stack([R * np.cos(angles_b), R * np.sin(angles_b), np.full(3, _TRIANGLE_GAP)], axis=1)
    pairs = [(0, 0), (0, 2), (1, 0), (1, 1), (2, 1), (2, 2)]
    return a, b, pairs


@dataclass(frozen=True)
class SuctionConstraints:
    """Six distance constraints between a cup and (at run time) the held part.

    Declared by :func:`declare_suction_constraints`. The constraints' bodies,
    points, lengths and active status live in the plant's Context: every new
    Context must go through :meth:`deactivate_all` (Drake makes constraints
    active in a new Context).
    """

    cup: BodyIndex
    ids: tuple[MultibodyConstraintId, ...]
    #: Constraint points in the cup frame: a_i (on the cup) and b_j (part side).
    p_CA: np.ndarray
    p_CB: np.ndarray
    pairs: tuple[tuple[int, int], ...]

    def deactivate_all(self, plant: MultibodyPlant, plant_context: Context) -> None:
        """Deactivates the six constraints (needed in every new Context)."""
        for id_ in self.ids:
            plant.SetConstraintActiveStatus(plant_context, id_, False)

    def held_body(self, plant: MultibodyPlant, plant_context: Context) -> Optional[BodyIndex]:
        """The body the active constraints hold; None when inactive."""
        if not plant.GetConstraintActiveStatus(plant_context, self.ids[0]):
            return None
        return plant.GetDistanceConstraintParams(plant_context, self.ids[0]).bodyB()

    def attach(self, plant: MultibodyPlant, plant_context: Context, part_body: RigidBody) -> RigidTransform:
        """Holds ``part_body`` at its current pose in the cup; returns that pose X_CP.

        The part's points are the octahedron's points b_j placed where they are
        now, so every constraint's length is its current length: nothing moves.
        """
        cup = plant.get_body(self.cup)
        if int(part_body.index()) == int(self.cup):
            raise ConfigError(f"suction: the cup {cup.name()!r} cannot hold itself")
        X_WC = plant.EvalBodyPoseInWorld(plant_context, cup)
        X_WP = plant.EvalBodyPoseInWorld(plant_context, part_body)
        X_CP = X_WC.InvertAndCompose(X_WP)
        X_PC = X_CP.inverse()
        for id_, (i, j) in zip(self.ids, self.pairs):
            p_CA, p_PB = self.p_CA[i], X_PC @ self.p_CB[j]
            distance = float(np.linalg.norm(X_WC @ p_CA - X_WP @ p_PB))
            plant.SetDistanceConstraintParams(
                plant_context,
                id_,
                DistanceConstraintParams(self.cup, p_CA, part_body.index(), p_PB, distance, math.inf, 0.0),
            )
            plant.SetConstraintActiveStatus(plant_context, id_, True)
        return X_CP

    def release(self, plant: MultibodyPlant, plant_context: Context) -> None:
        """Lets the held part go (deactivates the constraints)."""
        self.deactivate_all(plant, plant_context)


def declare_suction_constraints(
    plant: MultibodyPlant, cup_body: RigidBody, any_part_body: RigidBody
) -> SuctionConstraints:
    """Declares the weld backend's six distance constraints; call before ``plant.Finalize()``.

    ``any_part_body`` is a placeholder (any movable body other than the cup):
    :meth:`SuctionConstraints.attach` rewrites the constraints for the part
    actually held. The plant must use the SAP solver. Neither body may be the
    world body (constraints on it crash Drake 1.51's simulation).
    """
    if plant.is_finalized():
        raise StateError("declare_suction_constraints must be called before plant.Finalize()")
    solver = plant.get_discrete_contact_solver()
    if plant.time_step() <= 0 or solver != DiscreteContactSolver.kSap:
        raise ConfigError(
            "the weld backend needs a discrete plant with the SAP solver (time_step > 0, "
            "discrete_contact_approximation 'sap', 'lagged' or 'similar'); got time_step "
            f"{plant.time_step()} and {_approximation_name(plant)!r}"
        )
    world = int(plant.world_body().index())
    for body, what in ((cup_body, "cup"), (any_part_body, "placeholder part")):
        if int(body.index()) == world:
            raise ConfigError(f"suction {what} body cannot be the world body")
    if int(cup_body.index()) == int(any_part_body.index()):
        raise ConfigError(f"suction placeholder part must differ from the cup {cup_body.name()!r}")
    a, b, pairs = octahedron()
    ids = []
    for i, j in pairs:
        distance = float(np.linalg.norm(a[i] - b[j]))
        ids.append(plant.AddDistanceConstraint(cup_body, a[i], any_part_body, b[j], distance))
    return SuctionConstraints(cup_body.index(), tuple(ids), a, b, tuple(pairs))


def _approximation_name(plant: MultibodyPlant) -> str:
    """The plant's discrete contact approximation as spelt in MultibodyPlantConfig ("sap")."""
    return str(plant.get_discrete_contact_approximation()).rsplit(".k", 1)[-1].lower()
