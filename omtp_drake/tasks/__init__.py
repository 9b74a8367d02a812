"""Running a scenario's pick-and-place task and judging it; recording and plotting runs.

Lives here: ``run`` (``run_task``, ``TaskResult``), ``plots`` (``RunRecorder`` and
the ``plot_*`` functions, matplotlib).

May import: ``omtp_drake.viz``, ``omtp_drake.sim``, ``omtp_drake.control`` and below.
"""

from omtp_drake.tasks.run import TaskResult, TaskRun, prepare, run_task

__all__ = ["TaskResult", "TaskRun", "prepare", "run_task"]
