"""The parts in the world as ground truth (what Gazebo's model states say of them; they
are no links of a URDF): their names, poses in ``world`` and sizes, at
:data:`PARTS_RATE_HZ`, the logical cameras' default rate. The ROS 2 node publishes it
(``/omtp/parts``); the ROS 1 shim has Gazebo's ``/gazebo/model_states`` instead.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from pydrake.math import RigidTransform

from omtp_drake.gazebo.schedule import Periodic, Publication

if TYPE_CHECKING:
    from omtp_drake.script import Cell

PARTS_RATE_HZ = 10.0
#: The topic's name and its frame.
PARTS_TOPIC = "/omtp/parts"
PARTS_FRAME = "world"


@dataclass(frozen=True)
class PartPoses:
    """Every part in the world: names, poses ``X_WP`` and cube sizes (m), in one order."""

    stamp: float
    frame_id: str
    names: tuple[str, ...]
    poses: tuple[RigidTransform, ...]
    sizes: tuple[float, ...]


def parts_publication(cell: Cell) -> Publication:
    """The parts' poses (see the module doc)."""

    def message(t: float) -> PartPoses:
        names = tuple(cell.runtime.parts_in_world())
        poses = tuple(cell.part_pose(name) for name in names)
        sizes = tuple(cell.scenario.part_size(name) for name in names)
        return PartPoses(t, PARTS_FRAME, names, poses, sizes)

    return Publication(PARTS_TOPIC, PartPoses, Periodic(1.0 / PARTS_RATE_HZ, message), plugin="parts")
