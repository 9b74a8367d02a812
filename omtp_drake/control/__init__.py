"""Deciding how the arms move.

Lives here: tool paths for pick and place (``tool_paths``), the pick-and-place
controller (``pick_and_place``), and collision-aware joint motion planning
(``motion``).

May import: ``omtp_drake.cell`` and everything below it; not ``sim`` (control
reads the cell through ports and plant Contexts, not through the runtime).
"""
