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

from __future__ import annotations

from typing import TYPE_CHECKING

from omtp_drake.lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers (``X as X``: re-exported)
    from omtp_drake.batch.cluster import connect as connect
    from omtp_drake.batch.cluster import default_workers as default_workers
    from omtp_drake.batch.cluster import run_batch as run_batch
    from omtp_drake.batch.run_records import RunRecord as RunRecord
    from omtp_drake.batch.sandbox import Sandbox as Sandbox
    from omtp_drake.batch.sandbox import simulate as simulate
    from omtp_drake.batch.summary import format_summary as format_summary
    from omtp_drake.batch.summary import summarize as summarize
    from omtp_drake.batch.summary import wilson_interval as wilson_interval
    from omtp_drake.batch.sweep import parse_seeds as parse_seeds
    from omtp_drake.batch.sweep import parse_sets as parse_sets
    from omtp_drake.batch.sweep import plan_batch as plan_batch

#: The public names, by the module that defines them: each is imported on first use
#: (:mod:`omtp_drake.lazy`), so that importing one module of this package imports only it.
_MODULES = {
    "connect": ".cluster",
    "default_workers": ".cluster",
    "format_summary": ".summary",
    "parse_seeds": ".sweep",
    "parse_sets": ".sweep",
    "plan_batch": ".sweep",
    "run_batch": ".cluster",
    "RunRecord": ".run_records",
    "Sandbox": ".sandbox",
    "simulate": ".sandbox",
    "summarize": ".summary",
    "wilson_interval": ".summary",
}
__getattr__, __dir__ = lazy_names(__name__, _MODULES)

__all__ = sorted(_MODULES)
