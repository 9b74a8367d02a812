"""Many runs in parallel on Dask: sweeps, sandboxed runs, records, summaries and plots.

May import: ``omtp_drake.tasks`` and everything below it.
"""

from omtp_drake.batch.run import (
    RunRecord,
    connect,
    default_workers,
    format_summary,
    plan_batch,
    run_batch,
    simulate,
    summarize,
    wilson_interval,
)

__all__ = [
    "RunRecord",
    "connect",
    "default_workers",
    "format_summary",
    "plan_batch",
    "run_batch",
    "simulate",
    "summarize",
    "wilson_interval",
]
