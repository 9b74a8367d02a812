"""Deciding how the arms move.

Modules (one job each):

- ``tool_paths``: tool paths: timed segments and the poses along them
- ``pick_policy``: where the tool goes for a pick: grasps, bin slots, travels
- ``joint_plan``: DiffIK integrated ahead along a decided tool path into a joint plan (a B-spline in the
  Context) and the C++ jerk stream that plays it
- ``pick_and_place``: the pick-and-place controller: a pure state machine and the LeafSystem around it
- ``motion``: collision-aware joint motion planning (``ArmPlanner`` over one module per concept)

May import: ``omtp_drake.cell`` and everything below it; not ``sim`` (control
reads the cell through ports and plant Contexts, not through the runtime).
"""
