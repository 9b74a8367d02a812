"""Pick and place with differential IK: a state machine per robot.

Modules (one job each):

- ``controller_state``: what the controller is doing and has done, plain values (``Mode``,
  ``ControlState``, ``PickRecord``, ``PickFailure``, ``PickHistory``)
- ``perception``: parts and the bin as the logical cameras show them
- ``machine_io``: the state machine's plain inputs (``MachineInput``) and answers (``Decision``)
- ``recovery``: the machine's tool paths and the ends of failed attempts
- ``machine``: the pure state machine (``PickMachine``: plain inputs in, a ``Decision`` out)
- ``system``: the ``LeafSystem`` around it (``PickAndPlaceController``: the machine's decisions, the joint
  plan of each new tool path) and ``add_pick_and_place`` (it and its jerk stream)

Modules here import each other by module, never through this package.
"""

from omtp_drake.control.pick_and_place.controller_state import (
    ControlState,
    Mode,
    PickFailure,
    PickHistory,
    PickRecord,
)
from omtp_drake.control.pick_and_place.machine import (
    NO_IMAGE,
    Decision,
    MachineInput,
    PickMachine,
    bin_capacity,
    task_planner,
)
from omtp_drake.control.pick_and_place.system import (
    PickAndPlaceController,
    add_pick_and_place,
    control_of,
    history_of,
)

__all__ = [
    "NO_IMAGE",
    "ControlState",
    "Decision",
    "MachineInput",
    "Mode",
    "PickAndPlaceController",
    "PickFailure",
    "PickHistory",
    "PickMachine",
    "PickRecord",
    "add_pick_and_place",
    "bin_capacity",
    "control_of",
    "history_of",
    "task_planner",
]
