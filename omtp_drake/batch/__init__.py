"""Many runs in parallel on Dask: sweeps, sandboxed runs, records, summaries and plots.

Lives here: the plan of a batch, its seeds and settings parsed and checked
(``sweep``), a run isolated in a forked child of a runner subprocess
(``sandbox``), a run's outcome and the table of runs (``records``), the
results folder and resuming (``store``), the cluster and ``run_batch``
(``cluster``), the summary per setting (``summary``) and its figures (``plots``).

May import: ``omtp_drake.tasks`` and everything below it.
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
