"""FlexBE behaviours of the course (lecture 7) on the cell, headless, in simulated time.

    omtp-drake flexbe-run "Conveyor Pick" --workspace examples/flexbe --scenario lecture7_flexbe

or from Python::

    from omtp_drake.ros.flexbe import run_behavior
    report = run_behavior("Conveyor Pick", ["examples/flexbe"], scenario="lecture7_flexbe")

The engine (``flexbe_core``: Behavior, OperatableStateMachine, EventState,
ConcurrencyContainer, PriorityContainer, Autonomy, Logger and the proxies) and
``flexbe_states`` follow FlexBE's ROS 1 API; they live in this package and the
ROS-named modules in ``omtp_drake/ros/shims`` re-export them during a run.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from omtp_drake.ros.flexbe.report import FlexbeReport
    from omtp_drake.ros.flexbe.run import run_behavior

__all__ = ["FlexbeReport", "run_behavior"]


def __getattr__(name: str) -> Any:
    if name == "run_behavior":
        from omtp_drake.ros.flexbe.run import run_behavior

        return run_behavior
    if name == "FlexbeReport":
        from omtp_drake.ros.flexbe.report import FlexbeReport

        return FlexbeReport
    raise AttributeError(name)
