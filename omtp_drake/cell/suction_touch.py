"""What touches the suction cup: the candidate parts and the touch rule of a check.

:func:`part_body_indices` checks a gripper's candidate part bodies;
:func:`touching_part` is the rule a contact check applies (a part touching the
cup with the contact normal within the allowed angle of the tool axis, the
deepest if several); :func:`contact_points` counts the contacts between two
bodies. Frames as in :mod:`omtp_drake.cell.suction` (``C`` the cup, ``P`` a
part, ``W`` the world).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from pydrake.multibody.plant import ContactResults, MultibodyPlant
from pydrake.multibody.tree import RigidBody
from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError


def contact_points(plant: MultibodyPlant, plant_context: Context, body_a: int, body_b: int) -> int:
    """How many point contacts the plant's contact results have between the bodies with
    indices ``body_a`` and ``body_b`` (in either order) in ``plant_context``."""
    results = plant.get_contact_results_output_port().Eval(plant_context)
    pair = {int(body_a), int(body_b)}
    return sum(
        {int(info.bodyA_index()), int(info.bodyB_index())} == pair
        for info in (results.point_pair_contact_info(i) for i in range(results.num_point_pair_contacts()))
    )


def part_body_indices(
    plant: MultibodyPlant, cup: int, part_bodies: Sequence[RigidBody], name: str
) -> dict[str, int]:
    """The body index of each candidate part of gripper ``name`` (cup body index
    ``cup``), by body name. Raises ConfigError for none, the cup itself, an
    anchored body or a repeated name."""
    if not part_bodies:
        raise ConfigError(f"gripper {name!r} needs at least one candidate part body; got none")
    bodies: dict[str, int] = {}
    for body in part_bodies:
        if int(body.index()) == cup:
            raise ConfigError(f"gripper {name!r}: the cup {body.name()!r} cannot be its own part")
        if plant.IsAnchored(body):
            raise ConfigError(
                f"gripper {name!r}: part body {body.name()!r} is anchored (welded to the "
                "world); candidate parts must be movable"
            )
        if body.name() in bodies:
            raise ConfigError(f"gripper {name!r}: part body name {body.name()!r} is repeated")
        bodies[body.name()] = int(body.index())
    return bodies


def touching_part(
    contacts: ContactResults, cup: int, parts: Mapping[int, str], z_WC: np.ndarray, cos_max: float
) -> int:
    """Body index of the candidate part (a key of ``parts``) touching the cup body
    ``cup`` well, the deepest if several; -1 when none. A touch is good when the
    contact normal pointing from the part into the cup is within acos(``cos_max``)
    of -Cz (``z_WC``: the cup's +Cz in W).

    ``contacts`` may be a view of the plant's cache: evaluate nothing else while
    this reads it."""
    best, best_depth = -1, -math.inf
    for i in range(contacts.num_point_pair_contacts()):
        info = contacts.point_pair_contact_info(i)
        a, b = int(info.bodyA_index()), int(info.bodyB_index())
        if a == cup and b in parts:
            part, sign = b, 1.0  # nhat_BA_W points from B (part) into A (cup)
        elif b == cup and a in parts:
            part, sign = a, -1.0
        else:
            continue
        pair = info.point_pair()
        n_PC_W = sign * pair.nhat_BA_W  # from the part into the cup
        if -float(np.dot(n_PC_W, z_WC)) >= cos_max and pair.depth > best_depth:
            best, best_depth = part, pair.depth
    return best
