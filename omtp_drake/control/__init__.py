"""Deciding how the arms move.

Lives here: tool paths (``tool_paths``: timed segments and the poses along them),
where the tool goes for a pick (``pick_policy``: grasps, bin slots, travels), the pick-and-place
controller (``pick_and_place``: a pure state machine and the LeafSystem around
it), and collision-aware joint motion planning (``motion``: ``ArmPlanner`` over
one module per concept).

May import: ``omtp_drake.cell`` and everything below it; not ``sim`` (control
reads the cell through ports and plant Contexts, not through the runtime).
"""
