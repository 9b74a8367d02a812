"""A graded run's verdict, named for what happened, from how it ended and its report.

:func:`classify` decides from typed fields only, never from a message's text: the
isolated run's :class:`~omtp_drake.grading.isolation.Outcome` (the wall timeout, the
process limit, the signal it died of, its exit code, the output cut, the exception
its guard saw nothing catch) and the report ``ros-run`` or ``flexbe-run`` wrote
(absent when the process did not end on its own): its ``error`` (the exception's
classes and errno, :func:`omtp_drake.errors.exception_kind`), ``callback_errors``,
``collisions``, ``exit_code`` and ``timed_out``. Messages (the report's exception, the
end of stderr) only go into the verdict's words.
"""

from __future__ import annotations

import errno
import signal
from typing import Any, Optional

from omtp_drake.grading.isolation import Limits, Outcome

OK = "ok"
EXCEPTION = "exception"
COLLISION = "collision"
SIM_TIMEOUT = "simulated timeout"
WALL_TIMEOUT = "wall timeout"
MEMORY_LIMIT = "memory limit"
PROCESS_LIMIT = "process limit"
CPU_LIMIT = "cpu limit"
OUTPUT_CUT = "output cut"
EXITED_EARLY = "exited early"
KILLED = "killed by signal"
WORKER_DIED = "worker died"
#: Every verdict, in the order of the table's legend.
VERDICTS = (
    OK,
    OUTPUT_CUT,
    SIM_TIMEOUT,
    COLLISION,
    EXCEPTION,
    EXITED_EARLY,
    WALL_TIMEOUT,
    CPU_LIMIT,
    MEMORY_LIMIT,
    PROCESS_LIMIT,
    KILLED,
    WORKER_DIED,
)


def _out_of_memory(error: Optional[dict[str, Any]]) -> bool:
    """The exception (:func:`~omtp_drake.errors.exception_kind`) is the memory limit's:
    a MemoryError (C++'s ``std::bad_alloc`` arrives as one) or an OSError ENOMEM."""
    return error is not None and ("MemoryError" in error["kinds"] or error.get("errno") == errno.ENOMEM)


def _fork_refused(error: Optional[dict[str, Any]]) -> bool:
    """The exception is a new process refused at the process limit (EAGAIN from fork)."""
    return error is not None and error.get("errno") == errno.EAGAIN


def classify(
    outcome: Outcome, report: Optional[dict[str, Any]], stderr_tail: str, limits: Limits, wall_timeout: float
) -> tuple[str, str]:
    """(verdict, message) of one run; ``stderr_tail`` only goes into the message."""
    if outcome.process_limit:
        status, message = PROCESS_LIMIT, f"more than {limits.processes} processes (all killed)"
    elif report is not None and _out_of_memory(report.get("error")):  # however long its exit then took
        status, message = _from_report(report, limits)
    elif outcome.timed_out:
        status, message = WALL_TIMEOUT, f"over {wall_timeout:g} s wall time (killed)"
    elif outcome.signal == signal.Signals.SIGXCPU.name:
        status, message = CPU_LIMIT, f"over {limits.cpu_s} CPU seconds (killed by SIGXCPU)"
    elif report is None:
        status, message = _without_report(outcome, stderr_tail, limits)
    else:
        status, message = _from_report(report, limits)
        if status == OK and outcome.stdout.cut + outcome.stderr.cut:
            status = OUTPUT_CUT
    cut = outcome.stdout.cut + outcome.stderr.cut
    notes = [message] if message else []
    if cut:
        notes.append(f"{cut} bytes of output cut (kept {limits.output_kb} KB per stream)")
    if outcome.left_running:
        notes.append(f"{outcome.left_running} process(es) left running, killed")
    return status, "; ".join(notes)


def _without_report(outcome: Outcome, stderr_tail: str, limits: Limits) -> tuple[str, str]:
    tail = f": {stderr_tail}" if stderr_tail else ""
    if _out_of_memory(outcome.uncaught):
        return MEMORY_LIMIT, f"over the memory limit of {limits.memory_mb} MB{tail}"
    if outcome.signal:
        return KILLED, f"killed by {outcome.signal}{tail}"
    return EXITED_EARLY, f"exited early with code {outcome.returncode} (no report){tail}"


def _from_report(report: dict[str, Any], limits: Limits) -> tuple[str, str]:
    exception, error = report.get("exception"), report.get("error")
    if exception:
        if _out_of_memory(error):
            return MEMORY_LIMIT, f"over the memory limit of {limits.memory_mb} MB ({exception})"
        if _fork_refused(error):
            return PROCESS_LIMIT, f"a new process refused at the limit of {limits.processes} ({exception})"
        return EXCEPTION, exception
    if report.get("callback_errors"):
        return EXCEPTION, f"bad callback: {report['callback_errors'][0]}"
    if report.get("collisions"):
        return COLLISION, report["collisions"][0]
    if report.get("exit_code"):
        return EXITED_EARLY, f"the script's exit code {report['exit_code']} (SystemExit)"
    shutdown = report.get("shutdown") or ""
    if report.get("timed_out"):
        return SIM_TIMEOUT, shutdown
    return OK, shutdown
