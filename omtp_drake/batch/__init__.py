"""Many runs in parallel on Dask: sweeps, sandboxed runs, records, summaries and plots.

Modules (one job each):

- ``sweep``: a batch's plan: its seeds and settings parsed and checked
- ``sandbox``: a run isolated in a forked child of a runner subprocess
- ``run_records``: a run's outcome (``RunRecord``) and the table of runs (``runs.csv``)
- ``store``: the results folder: a JSON per run (resuming), the table, summary and plots
- ``cluster``: the Dask cluster and ``run_batch``
- ``summary``: what a batch adds up to per setting (success rate, cycle times, failures)
- ``plots``: a batch's figures: success rate per setting and cycle-time histograms
- ``command``: ``omtp-drake batch`` and the progress-bar options of the task commands

May import: ``omtp_drake.tasks`` and everything below it (``launch``: a batch of a student's own cell).
"""

from omtp_drake.batch.cluster import connect, default_workers, run_batch
from omtp_drake.batch.run_records import RunRecord
from omtp_drake.batch.sandbox import Sandbox, simulate
from omtp_drake.batch.summary import format_summary, summarize, wilson_interval
from omtp_drake.batch.sweep import parse_seeds, parse_sets, plan_batch

__all__ = [
    "RunRecord",
    "Sandbox",
    "connect",
    "default_workers",
    "format_summary",
    "parse_seeds",
    "parse_sets",
    "plan_batch",
    "run_batch",
    "simulate",
    "summarize",
    "wilson_interval",
]
