"""Running a scenario's pick-and-place task and judging it; recording and plotting runs.

Modules (one job each):

- ``run``: ``run_task`` and ``TaskResult``: a scenario's task run and judged
- ``plots``: ``RunRecorder`` and the ``plot_*`` functions of a run (matplotlib)

May import: ``omtp_drake.viz``, ``omtp_drake.sim``, ``omtp_drake.control`` and below.
"""

from omtp_drake.tasks.run import TaskResult, TaskRun, prepare, run_task

__all__ = ["TaskResult", "TaskRun", "prepare", "run_task"]
