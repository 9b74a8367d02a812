"""Pick and place with differential IK: a state machine per robot.

- :mod:`~omtp_drake.control.pick_and_place.controller_state`: what the controller is doing
  and has done (:class:`Mode`, :class:`ControlState`, :class:`PickRecord`,
  :class:`PickFailure`, :class:`PickHistory`), plain values;
- :mod:`~omtp_drake.control.pick_and_place.perception`: parts and the bin as the
  logical cameras show them;
- :mod:`~omtp_drake.control.pick_and_place.machine_io`: the state machine's plain
  inputs (:class:`MachineInput`) and answers (:class:`Decision`);
- :mod:`~omtp_drake.control.pick_and_place.recovery`: its tool paths and the ends
  of failed attempts;
- :mod:`~omtp_drake.control.pick_and_place.machine`: the pure state machine
  (:class:`PickMachine`: plain inputs in, a :class:`Decision` out; no Drake system);
- :mod:`~omtp_drake.control.pick_and_place.system`: the ``LeafSystem`` around it
  (:class:`PickAndPlaceController`) and :func:`add_pick_and_place`.

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
