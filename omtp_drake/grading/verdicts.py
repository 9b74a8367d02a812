"""A graded run's verdict, named for what happened, from how it ended and its report.

:func:`classify` reads the isolated run's :class:`~omtp_drake.grading.isolation.Outcome`
(the wall timeout, the process limit, the signal it died of, its exit code, the
output cut), the report ``ros-run`` wrote (absent when the process did not end
on its own) and the end of its stderr; :func:`refusals` finds what the sandbox
refused in the same texts.
"""

from __future__ import annotations

import re
from typing import Any, Optional

from omtp_drake.grading.guard import REFUSED
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

_MEMORY = ("MemoryError", "std::bad_alloc", "Cannot allocate memory")
_FORK_REFUSED = "[Errno 11] Resource temporarily unavailable"


def classify(
    outcome: Outcome, report: Optional[dict[str, Any]], stderr_tail: str, limits: Limits, wall_timeout: float
) -> tuple[str, str]:
    """(verdict, message) of one run."""
    exception = (report or {}).get("exception") or ""
    if outcome.process_limit:
        status, message = PROCESS_LIMIT, f"more than {limits.processes} processes (all killed)"
    elif any(m in exception for m in _MEMORY):  # however long its process then took to exit
        status, message = _from_report(report or {}, limits)
    elif outcome.timed_out:
        status, message = WALL_TIMEOUT, f"over {wall_timeout:g} s wall time (killed)"
    elif outcome.signal == "SIGXCPU":
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
    if any(m in stderr_tail for m in _MEMORY):
        return MEMORY_LIMIT, f"over the memory limit of {limits.memory_mb} MB{tail}"
    if outcome.signal:
        return KILLED, f"killed by {outcome.signal}{tail}"
    return EXITED_EARLY, f"exited early with code {outcome.returncode} (no report){tail}"


def _from_report(report: dict[str, Any], limits: Limits) -> tuple[str, str]:
    exception = report.get("exception") or ""
    if report.get("callback_errors") and not exception:
        exception = f"bad callback: {report['callback_errors'][0]}"
    if exception:
        if any(m in exception for m in _MEMORY):
            return MEMORY_LIMIT, f"over the memory limit of {limits.memory_mb} MB ({exception})"
        if _FORK_REFUSED in exception:
            return PROCESS_LIMIT, f"a new process refused at the limit of {limits.processes} ({exception})"
        return EXCEPTION, exception
    if report.get("collisions"):
        return COLLISION, report["collisions"][0]
    if report.get("exit_code"):
        return EXITED_EARLY, f"the script's exit code {report['exit_code']} (SystemExit)"
    shutdown = report.get("shutdown") or ""
    if shutdown.startswith("--timeout"):
        return SIM_TIMEOUT, shutdown
    return OK, shutdown


_EROFS = re.compile(r"\[Errno 30\] Read-only file system: '([^']*)'")
_EROFS_PROGRAM = re.compile(r"(/[^\s:'\"]*): Read-only file system")  # a program's message (sh, touch)
_NETWORK = re.compile(r"\[Errno (101|99|97)\] [^(|;]*")


def refusals(*texts: str) -> str:
    """What the sandbox refused, as found in ``texts`` (the report's exception, stderr)."""
    found: list[str] = []
    for text in texts:
        for m in re.finditer(re.escape(REFUSED) + r": ([^|;\n]*?\))", text):
            found.append(m.group(1).strip())
        found += [f"write to {m.group(1)} (read-only)" for m in _EROFS.finditer(text)]
        found += [f"write to {m.group(1)} (read-only)" for m in _EROFS_PROGRAM.finditer(text)]
        found += [f"network ({m.group(0).strip()})" for m in _NETWORK.finditer(text)]
    return "; ".join(dict.fromkeys(found))
