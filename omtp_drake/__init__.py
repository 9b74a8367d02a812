"""omtp_drake: the OMTP factory cell of the object-detection-and-grasping course in Drake.

The usual entry points::

    from omtp_drake import Cell, tool_down          # script the cell yourself
    from omtp_drake import FactoryRuntime           # the cell and its services
    from omtp_drake import run_task, load_scenario  # a scenario's pick-and-place task

``import omtp_drake`` loads nothing heavy: each name is imported on first use.

Modules and packages, bottom to top (one imports only from those below it; the order
is held and checked by tests/test_layering.py):

- ``errors``: one exception hierarchy for every user-facing error
- ``assets``: model files: the project's xacro sources and the classic UR arms
- ``workspace``: a student's own ROS workspace: packages and Gazebo models by name
- ``scenario``: the typed schema of ``diagrams/*.yaml`` and its loader
- ``cell``: what the factory is made of, as Drake systems and models
- ``sim``: running the cell: the driver, its world edits, the part pool and services
- ``control``: deciding how the arms move: tool paths, pick and place, motion planning
- ``viz``: looking at the cell: Meshcat views and replays, screenshots, the frame tree
- ``launch``: a student's own cell: their launch files, worlds, URDF/xacro and Gazebo plugins
- ``tasks``: a scenario's pick-and-place task, run and judged; plots of a run
- ``script``: scripting the cell yourself: ``Cell`` and its arms, grippers and cameras
- ``batch``: many runs in parallel on Dask, their records, summaries and plots
- ``gazebo``: Gazebo's ROS plugins defined once, transport-neutral, under the ROS 1 shim and the ROS 2 node
- ``ros``: the course's ROS 1 scripts and FlexBE behaviours, unchanged, on the cell
- ``demos``: ready-made runs of the factory for the command line
- ``bench_command``: ``omtp-drake bench``'s link to the benchmarks in ``bench/``
- ``grading``: a class's ROS scripts or behaviours graded: each run isolated, one verdict each
- ``ros2``: the cell as ROS 2 nodes over DDS, for rclpy code, ``ros2`` tools and rviz2
- ``cli``: the ``omtp-drake`` command line
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_LAZY = {
    "Cell": "omtp_drake.script",
    "FactoryRuntime": "omtp_drake.sim.runtime",
    "load_scenario": "omtp_drake.scenario",
    "run_task": "omtp_drake.tasks",
    "tool_down": "omtp_drake.control.tool_paths",
}

__all__ = ["Cell", "FactoryRuntime", "load_scenario", "run_task", "tool_down"]

if TYPE_CHECKING:
    from omtp_drake.control.tool_paths import tool_down
    from omtp_drake.scenario import load_scenario
    from omtp_drake.script import Cell
    from omtp_drake.sim.runtime import FactoryRuntime
    from omtp_drake.tasks import run_task


def __getattr__(name: str) -> Any:
    if name not in _LAZY:
        raise AttributeError(f"module 'omtp_drake' has no attribute {name!r}")
    value = getattr(importlib.import_module(_LAZY[name]), name)
    globals()[name] = value
    return value
