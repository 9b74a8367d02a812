"""One untrusted ``ros-run`` isolated: its own copy of its folder, limits, a sandbox, output capped.

:func:`run_isolated` starts ``python -m omtp_drake.grading.cli ros-run ...`` with
the guard's settings in its environment (it sets the limits and refuses writes
outside the copy, network and signals to other processes, see
:mod:`omtp_drake.grading.guard`) in a session of its own, inside bubblewrap when
the sandbox is ``bwrap``: the whole system read-only, the run's folder the only
writable place, a private ``/tmp``, no network, its own process, IPC and user
namespaces, killed with its parent.

The grader never waits on the run's pipes: a reader thread copies stdout and
stderr to files up to :attr:`Limits.output_kb` each and counts the rest. It
watches the run's processes (every descendant, and every process of its
session) and kills them all when there are more than :attr:`Limits.processes`,
at the wall timeout, and always when the run ends: no process outlives it.
"""

from __future__ import annotations

import argparse
import errno
import functools
import json
import logging
import os
import re
import select
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import IO, Any, Optional

from omtp_drake.errors import ConfigError
from omtp_drake.grading.guard import ENV, ProcessScan, descendants, process_table, read_records

_log = logging.getLogger(__name__)

BWRAP = "/usr/bin/bwrap"
SANDBOXES = ("auto", "bwrap", "none")
#: Seconds between two looks at the run's processes.
_POLL_S = 0.05
#: The file in the run's folder where its guard keeps its records (refusals, an uncaught
#: exception, the processes it leaves at its exit; see :mod:`omtp_drake.grading.guard`).
RECORDS_FILE = ".guard_records.jsonl"
#: Processes bubblewrap adds (its own, and the namespace's init).
_BWRAP_PROCESSES = 2


@dataclass(frozen=True)
class Limits:
    """Per run: address space, processes, CPU seconds, open files, output kept per stream."""

    memory_mb: int = 4096
    processes: int = 64
    cpu_s: int = 600
    open_files: int = 1024
    output_kb: int = 1024

    def check(self) -> None:
        for name, value in asdict(self).items():
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ConfigError(
                    f"the {name.replace('_', ' ')} limit must be an integer >= 1, got {value!r}"
                )
        if self.memory_mb < 1024:
            raise ConfigError(f"the memory limit must be >= 1024 MB (a run needs ~500), got {self.memory_mb}")

    def describe(self) -> str:
        return (
            f"memory {self.memory_mb} MB, {self.processes} processes, {self.cpu_s} CPU s, "
            f"{self.open_files} open files, output {self.output_kb} KB per stream"
        )


@dataclass
class StreamLog:
    """One captured stream: its file, the bytes kept there and the bytes cut."""

    path: str
    kept: int = 0
    cut: int = 0


@dataclass
class Outcome:
    """How an isolated run ended."""

    returncode: Optional[int]
    signal: Optional[str]
    wall_s: float
    timed_out: bool = False
    process_limit: bool = False
    peak_processes: int = 0
    left_running: int = 0
    stdout: StreamLog = field(default_factory=lambda: StreamLog(""))
    stderr: StreamLog = field(default_factory=lambda: StreamLog(""))
    #: What the guard refused, one record each: ``{"refused": audit event, "what": ...}``.
    refused: list[dict[str, Any]] = field(default_factory=list)
    #: The exception nothing in the run caught, as its guard recorded it
    #: (:func:`omtp_drake.errors.exception_kind`); None: none.
    uncaught: Optional[dict[str, Any]] = None


@functools.cache
def bwrap_works() -> bool:
    """True when bubblewrap runs here with the namespaces the sandbox uses."""
    if not os.access(BWRAP, os.X_OK):
        return False
    import tempfile

    with tempfile.TemporaryDirectory(prefix="omtp-bwrap-") as tmp:
        command = sandbox_prefix(Path(tmp), Path(tmp)) + ["true"]
        try:
            done = subprocess.run(command, capture_output=True, timeout=20)
        except (OSError, subprocess.TimeoutExpired) as e:
            _log.info("bubblewrap does not run here: %s", e)
            return False
    if done.returncode != 0:
        _log.info("bubblewrap does not run here: %s", done.stderr.decode(errors="replace").strip())
    return done.returncode == 0


@functools.cache
def resolve_sandbox(choice: str) -> str:
    """``bwrap`` or ``none`` for ``--sandbox choice`` (``auto``: bubblewrap when it works,
    else one warning)."""
    if choice not in SANDBOXES:
        raise ConfigError(f"--sandbox {choice!r} is unknown; valid: {', '.join(SANDBOXES)}")
    if choice == "none":
        return "none"
    if bwrap_works():
        return "bwrap"
    if choice == "bwrap":
        raise ConfigError(f"--sandbox bwrap: {BWRAP} is missing or cannot create namespaces here")
    _log.warning("no working bubblewrap (%s): scripts run with the limits and the Python guard only", BWRAP)
    return "none"


def _software_in_tmp() -> list[Path]:
    """What the run's own Python needs that lives under /tmp (a checkout or a virtual
    environment there, as in a fresh clone): its prefix, its path entries, the model cache."""
    from omtp_drake.assets import cache_dir

    wanted = [Path(sys.prefix), Path(sys.executable).parent, cache_dir()]
    wanted += [Path(p) for p in sys.path if p]
    found: list[Path] = []
    for path in wanted:
        real = path.resolve()
        if real.parts[:2] == ("/", "tmp") and len(real.parts) > 2 and real.exists():
            found.append(real)
    tops = sorted(set(found), key=lambda p: len(p.parts))
    return [p for i, p in enumerate(tops) if not any(p.is_relative_to(q) for q in tops[:i])]


def sandbox_prefix(work: Path, cwd: Path, readable: Sequence[Path] = ()) -> list[str]:
    """The bubblewrap command line before the command: ``work`` the only writable folder,
    ``readable`` folders of the hidden /tmp (and the run's own software there) shown read-only."""
    shown = [a for p in [*_software_in_tmp(), *readable] for a in ("--ro-bind", str(p), str(p))]
    return [
        BWRAP,
        "--ro-bind", "/", "/",
        "--dev", "/dev",
        "--proc", "/proc",
        "--tmpfs", "/tmp",
        *shown,
        "--bind", str(work), str(work),
        "--unshare-user", "--unshare-pid", "--unshare-net", "--unshare-ipc", "--unshare-uts",
        "--unshare-cgroup-try",
        "--die-with-parent", "--new-session", "--cap-drop", "ALL",
        "--chdir", str(cwd),
        "--",
    ]  # fmt: skip


def guarded_command(
    ros_args: Sequence[str],
    *,
    work: Path,
    cwd: Path,
    script: Path,
    sandbox: str,
    limits: Limits,
    readable: Sequence[Path] = (),
) -> tuple[list[str], dict[str, str]]:
    """The command and environment of ``ros-run ros_args`` under the guard (and bubblewrap).

    The simulator's own files are not the run's: the model cache (filled before the
    run, :func:`omtp_drake.grading.grade.prepare_cell`) is read-only to it, and what
    the cache lacks goes to a layer in the run's temporary folder
    (:func:`omtp_drake.assets.cache_entry`), as do Drake's and matplotlib's files: none
    of them is a refusal of the guard's, which records the script's own acts only."""
    from omtp_drake.assets import CACHE_LAYER_ENV, cache_dir

    tmp = Path("/tmp") if sandbox == "bwrap" else work / ".tmp"
    settings = {
        "limits": asdict(limits),
        "writable": [str(work), str(tmp)],
        "script": str(script),
        "parent": 0 if sandbox == "bwrap" else os.getpid(),
        "in_namespace": sandbox == "bwrap",
        "records": str(work / RECORDS_FILE),
    }
    env = dict(os.environ)
    env.update(
        {
            ENV: json.dumps(settings),
            "PYTHONPATH": os.pathsep.join(p for p in sys.path if p),
            "PYTHONDONTWRITEBYTECODE": "1",
            "TMPDIR": str(tmp),
            "MPLCONFIGDIR": str(tmp / "matplotlib"),
            "OMP_NUM_THREADS": "1",
            "OMTP_DRAKE_CACHE": str(cache_dir().parent),
            CACHE_LAYER_ENV: str(tmp / "omtp_drake_cache"),
        }
    )
    command = [sys.executable, "-m", "omtp_drake.grading.cli", *ros_args]
    if sandbox == "bwrap":
        command = sandbox_prefix(work, cwd, readable) + command
    else:
        tmp.mkdir(exist_ok=True)
    return command, env


def run_isolated(
    command: Sequence[str],
    env: dict[str, str],
    *,
    cwd: Path,
    limits: Limits,
    wall_timeout: float,
    logs: tuple[Path, Path],
    sandbox: str,
    session_file: Optional[Path] = None,
) -> Outcome:
    """Runs ``command`` (from :func:`guarded_command`) to its end, the wall timeout or the
    process limit; every process it started is dead when this returns. ``session_file``
    gets the run's session id (for :func:`kill_session` when this process dies first)."""
    start = time.monotonic()
    proc = subprocess.Popen(
        list(command),
        cwd=str(cwd),
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    assert proc.stdout is not None and proc.stderr is not None
    if session_file is not None:
        session_file.write_text(f"{proc.pid}\n")
    cap = limits.output_kb << 10
    streams = (StreamLog(str(logs[0])), StreamLog(str(logs[1])))
    reader = threading.Thread(
        target=_copy_capped, args=((proc.stdout, proc.stderr), streams, cap), daemon=True
    )
    reader.start()
    outcome = Outcome(None, None, 0.0, stdout=streams[0], stderr=streams[1])
    own = _BWRAP_PROCESSES if sandbox == "bwrap" else 0
    seen = {p: t for p, (_, _, t) in process_table().items() if p == proc.pid}
    left = 0
    try:
        left = _watch(proc, seen, outcome, limits.processes + own, start + wall_timeout, own)
    finally:
        # Left over: besides the run's main process (and, under bubblewrap, the namespace's init).
        outcome.left_running = max(0, _kill_all(proc, seen) - own)
        at_exit = _read_guard_records(env, outcome)
        if sandbox == "bwrap" and not (outcome.timed_out or outcome.process_limit):
            # The namespace's processes die with the run's own: counted by the run at its
            # exit (the guard), and at the grader's last look.
            outcome.left_running = max(outcome.left_running, left, at_exit)
        outcome.wall_s = time.monotonic() - start
        outcome.peak_processes -= own
        reader.join(timeout=5.0)
        for pipe in (proc.stdout, proc.stderr):
            pipe.close()
    code = proc.returncode
    if code is not None and code < 0:
        outcome.signal = _signal_name(-code)
    elif sandbox == "bwrap" and code is not None and code > 128:  # bubblewrap: 128 + the signal
        outcome.signal = _signal_name(code - 128)
    outcome.returncode = code
    return outcome


def _read_guard_records(env: dict[str, str], outcome: Outcome) -> int:
    """The run's guard's records into ``outcome`` (its refusals, an uncaught exception); how
    many processes the run left running at its exit (0: not recorded)."""
    left = 0
    path = json.loads(env[ENV]).get("records") if ENV in env else None
    for record in read_records(path) if path else []:
        if "refused" in record:
            outcome.refused.append(record)
        elif "uncaught" in record:
            outcome.uncaught = record["uncaught"]
        elif "left_running" in record:
            left = int(record["left_running"])
    return left


def _watch(
    proc: subprocess.Popen, seen: dict[int, int], outcome: Outcome, most: int, deadline: float, own: int
) -> int:
    """Looks at the run's processes every :data:`_POLL_S` until it ends, has more than
    ``most`` processes or passes ``deadline`` (``outcome`` says which); how many processes
    besides the sandbox's ``own`` and the run's main one there were at the last look."""
    left, main = 0, proc.pid if own == 0 else 0
    scan = ProcessScan()
    while proc.poll() is None:
        table = scan.table(seen)
        tree = _run_processes(proc.pid, seen, table)
        scan.remember_others(table, tree)
        seen.update(tree)
        if not main:  # the first process under the sandbox's own chain is the run's
            main = next(iter(_chain_children(proc.pid, own - 1, table)), 0)
        left = len(tree) - own - (1 if main in tree else 0)
        outcome.peak_processes = max(outcome.peak_processes, len(tree))
        if len(tree) > most:
            outcome.process_limit = True
            break
        if time.monotonic() > deadline:
            outcome.timed_out = True
            break
        time.sleep(_POLL_S)
    return max(0, left)


def _chain_children(root: int, depth: int, table: dict[int, tuple[int, int, int]]) -> list[int]:
    """The children of the processes ``depth`` generations below ``root``."""
    level = [root]
    for _ in range(depth):
        level = [p for p, (ppid, _, _) in table.items() if ppid in level]
    return [p for p, (ppid, _, _) in table.items() if ppid in level]


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def _copy_capped(pipes: tuple[IO[bytes], IO[bytes]], logs: tuple[StreamLog, StreamLog], cap: int) -> None:
    """Copies each pipe to its log file, the first ``cap`` bytes; counts the rest; ends at EOF on both."""
    files = {p.fileno(): (open(log.path, "wb"), log) for p, log in zip(pipes, logs)}
    try:
        while files:
            for fd in select.select(list(files), [], [], 1.0)[0]:
                f, log = files[fd]
                chunk = os.read(fd, 1 << 16)
                if not chunk:
                    f.close()
                    del files[fd]
                    continue
                room = max(0, cap - log.kept)
                if room:
                    f.write(chunk[:room])
                    log.kept += min(room, len(chunk))
                log.cut += max(0, len(chunk) - room)
    except (OSError, ValueError):
        pass  # the pipes were closed under us: the run is over
    finally:
        for f, _ in files.values():
            f.close()


def _run_processes(
    root: int, seen: dict[int, int], table: Optional[dict[int, tuple[int, int, int]]] = None
) -> dict[int, int]:
    """pid -> start time of the live processes of the run: descendants of ``root`` and of
    any process seen before (the same process: same start time), and every process of
    ``root``'s session."""
    table = process_table() if table is None else table
    found = {p: t for p, (_, sid, t) in table.items() if sid == root}
    found.update({p: t for p, t in seen.items() if p in table and table[p][2] == t})
    found.update({p: table[p][2] for p in descendants(found, table)})
    return found


def _kill_all(proc: subprocess.Popen, seen: dict[int, int]) -> int:
    """SIGKILLs the run's process group and every process of the run until none is left;
    how many there were besides the run's own process."""
    left = 0
    for attempt in range(200):
        alive = set(_run_processes(proc.pid, seen))
        if attempt == 0:
            left = len(alive - {proc.pid})
        if not alive:
            break
        for pid in alive:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except OSError:
            pass
        time.sleep(0.01)
    proc.wait()
    return left


def kill_session(session: int) -> int:
    """SIGKILLs every process of the session ``session`` (a run whose grader died); how many."""
    victims = [p for p, (_, sid, _) in process_table().items() if sid == session]
    for pid in victims:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    return len(victims)


#: The limit flags: (flag, the Limits field, metavar, what it limits).
_LIMIT_FLAGS = (
    ("--memory", "memory_mb", "MB", "address space per run"),
    ("--processes", "processes", "N", "processes per run"),
    ("--cpu", "cpu_s", "S", "CPU seconds per run"),
    ("--open-files", "open_files", "N", "open files per run"),
    ("--output", "output_kb", "KB", "output kept per stream, the rest cut and counted"),
)


def add_isolation_flags(parser: argparse.ArgumentParser, *, sandbox_default: Optional[str]) -> None:
    """``--sandbox`` and the limit flags of ``grade`` and ``ros-run``."""
    d = Limits()
    parser.add_argument(
        "--sandbox",
        choices=SANDBOXES,
        default=sandbox_default,
        help="bwrap: bubblewrap (read-only system, no network, private /tmp); none: limits and the "
        f"Python guard only; auto: bwrap when it works (default: {sandbox_default or 'not isolated'})",
    )
    for flag, field_name, metavar, what in _LIMIT_FLAGS:
        parser.add_argument(
            flag,
            dest=field_name,
            type=int,
            default=getattr(d, field_name),
            metavar=metavar,
            help=f"{what} (default %(default)s)",
        )


def limits_from_args(args: argparse.Namespace) -> Limits:
    limits = Limits(**{field_name: getattr(args, field_name) for _, field_name, _, _ in _LIMIT_FLAGS})
    limits.check()
    return limits


#: The errnos of the kernel's refusals inside bubblewrap: a read-only file system, no network.
_READ_ONLY, _NO_NETWORK = errno.EROFS, (errno.ENETUNREACH, errno.EADDRNOTAVAIL, errno.EAFNOSUPPORT)
#: How another program (a shell, ``touch``) says the kernel refused a write: its output is the
#: only trace of it (no record, no exception of the run's own).
_PROGRAM_READ_ONLY = re.compile(r"(/[^\s:'\"]*): Read-only file system")


def refusals(outcome: Outcome, error: Optional[dict[str, Any]], stderr_tail: str) -> str:
    """What the sandbox refused the run, on one line: the guard's records, the kernel's
    refusal the run's exception is (``error``: its errno), and writes other programs the
    run started said were refused (in ``stderr_tail``)."""
    found = [r["what"] for r in outcome.refused]
    if error and error.get("errno") == _READ_ONLY:
        found.append(f"write to {error.get('filename') or '?'} (read-only)")
    if error and error.get("errno") in _NO_NETWORK:
        found.append(f"network ({os.strerror(error['errno'])})")
    found += [f"write to {m.group(1)} (read-only)" for m in _PROGRAM_READ_ONLY.finditer(stderr_tail)]
    return "; ".join(dict.fromkeys(found))
