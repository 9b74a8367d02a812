"""FlexBE behaviours of the course (lecture 7) on the cell, headless, in simulated time.

    omtp-drake flexbe-run "Conveyor Pick" --workspace examples/flexbe --scenario lecture7_flexbe

or from Python::

    from omtp_drake.ros.flexbe import run_behavior
    report = run_behavior("Conveyor Pick", ["examples/flexbe"], scenario="lecture7_flexbe")

The engine (``flexbe_core``) and ``flexbe_states`` follow FlexBE's ROS 1 API; they
live in this package and the ROS-named modules in ``omtp_drake/ros/shims``
re-export them during a run.

Modules (one job each):

- ``engine``: the state machine engine: EventState, OperatableStateMachine, Autonomy, Logger
- ``containers``: ConcurrencyContainer and PriorityContainer
- ``behavior``: Behavior: a name, parameters, contained behaviours and ``create()``
- ``userdata``: the data a state machine hands from state to state
- ``states``: ``flexbe_states``: the states FlexBE ships, with its parameters and outcomes
- ``proxies``: FlexBE's proxies (``flexbe_core.proxy``) on the run's ROS session
- ``topics``: ``rostopic``'s look-ups of a topic's type on the run's ROS session
- ``context``: one run's clock, autonomy level, trace of states, log lines and proxies
- ``workspace``: catkin workspaces: packages, importable Python, behaviour manifests
- ``run``: ``run_behavior``: a behaviour of catkin workspaces on a cell, in simulated time
- ``report``: the report of one ``flexbe-run``: outcome, trace, log lines, ledger, times
- ``cli``: the ``flexbe-run`` command
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
