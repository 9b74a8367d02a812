"""omtp_drake: the OMTP factory cell of the object-detection-and-grasping course in Drake.

The public API is the names below, all importable from here (``from omtp_drake import
Cell``); ``import omtp_drake`` loads nothing heavy: each name is imported on first use.
What lives in the subpackages is the implementation: it may change between versions.

- a cell to script (live view, replay, tf, cameras, arms, grippers, parts):
  :class:`Cell`, :func:`tool_down`, :func:`yaw_of`
- the cell and its services without the script's handles: :class:`FactoryRuntime`,
  :class:`TfBuffer` (tf2's buffer on a runtime's Context), :func:`load_scenario`
- the frame tree, as ROS ``view_frames`` draws it: :func:`view_frames`
- a scenario's pick-and-place task, and plots of a run: :func:`run_task`,
  :class:`RunRecorder`, :func:`plot_tracking_error`, :func:`plot_detections`,
  :func:`plot_conveyor`, :func:`plot_cycle_times`, :func:`plot_ledger`, :func:`plot_seed_stats`
- many runs at once on Dask: :func:`run_batch`, :func:`summarize`, :func:`format_summary`

Modules and packages, bottom to top (one imports only from those below it; the order
is held and checked by tests/test_layering.py):

- ``errors``: one exception hierarchy for every user-facing error
- ``convex_pieces``: a mesh as convex pieces that keep it open (an open bin's skin)
- ``lazy``: a package's public names, imported from their modules on first use
- ``assets``: model files: the project's xacro sources, meshes for Drake, the model cache
- ``ur_arms``: the classic UR arms from example-robot-data, prefixed and Drake-ready
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

from typing import TYPE_CHECKING

from omtp_drake.lazy import lazy_names

#: The public names, by the module that defines them.
_LAZY = {
    "Cell": "omtp_drake.script",
    "FactoryRuntime": "omtp_drake.sim.runtime",
    "RunRecorder": "omtp_drake.tasks.plots",
    "TfBuffer": "omtp_drake.sim.tf",
    "format_summary": "omtp_drake.batch",
    "load_scenario": "omtp_drake.scenario",
    "plot_conveyor": "omtp_drake.tasks.plots",
    "plot_cycle_times": "omtp_drake.tasks.plots",
    "plot_detections": "omtp_drake.tasks.plots",
    "plot_ledger": "omtp_drake.tasks.plots",
    "plot_seed_stats": "omtp_drake.tasks.plots",
    "plot_tracking_error": "omtp_drake.tasks.plots",
    "run_batch": "omtp_drake.batch",
    "run_task": "omtp_drake.tasks",
    "summarize": "omtp_drake.batch",
    "tool_down": "omtp_drake.control.tool_paths",
    "view_frames": "omtp_drake.viz.tree",
    "yaw_of": "omtp_drake.control.tool_paths",
}

__all__ = list(_LAZY)

if TYPE_CHECKING:  # the names for type checkers (``X as X``: re-exported)
    from omtp_drake.batch import format_summary as format_summary
    from omtp_drake.batch import run_batch as run_batch
    from omtp_drake.batch import summarize as summarize
    from omtp_drake.control.tool_paths import tool_down as tool_down
    from omtp_drake.control.tool_paths import yaw_of as yaw_of
    from omtp_drake.scenario import load_scenario as load_scenario
    from omtp_drake.script import Cell as Cell
    from omtp_drake.sim.runtime import FactoryRuntime as FactoryRuntime
    from omtp_drake.sim.tf import TfBuffer as TfBuffer
    from omtp_drake.tasks import run_task as run_task
    from omtp_drake.tasks.plots import RunRecorder as RunRecorder
    from omtp_drake.tasks.plots import plot_conveyor as plot_conveyor
    from omtp_drake.tasks.plots import plot_cycle_times as plot_cycle_times
    from omtp_drake.tasks.plots import plot_detections as plot_detections
    from omtp_drake.tasks.plots import plot_ledger as plot_ledger
    from omtp_drake.tasks.plots import plot_seed_stats as plot_seed_stats
    from omtp_drake.tasks.plots import plot_tracking_error as plot_tracking_error
    from omtp_drake.viz.tree import view_frames as view_frames


__getattr__, __dir__ = lazy_names(__name__, _LAZY)
