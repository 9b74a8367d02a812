"""The first code of an isolated ``ros-run``: its resource limits and its write/network/signal guard.

An isolated ``ros-run`` (started by :mod:`omtp_drake.grading.isolation`, inside
bubblewrap when there is one) has its settings in the ``OMTP_GUARD``
environment variable (JSON: ``limits``, ``writable`` folders, ``script``,
``parent``); the command line calls :func:`install_from_env` first, which,
before anything of the script runs:

- sets the resource limits (``RLIMIT_AS``, ``RLIMIT_CPU``, ``RLIMIT_NOFILE``,
  and ``RLIMIT_NPROC`` where it counts only this run's processes: inside
  bubblewrap's user namespace);
- asks the kernel to kill it when its parent (the grader) dies;
- keeps its records for the grader, one JSON object a line, in the settings'
  ``records`` file (in the run's folder): each refusal (``{"refused": event, "what": ...}``), an
  exception nothing caught (``{"uncaught": exception_kind}``) and, at its exit,
  how many processes it leaves running (``{"left_running": n}``: a sandbox that
  ends with the run kills them before the grader could count them from outside);
- installs a Python audit hook, armed when the script's own code starts, that
  refuses (``PermissionError``, message starting with :data:`REFUSED`, and a
  record) a file written, created, moved or deleted outside the writable
  folders, a network connection, and a signal to a process outside the run's session.

The hook sees what the script does through Python; a script that goes through
``ctypes`` or another program gets past it. Without bubblewrap it is the only
guard; with bubblewrap the kernel refuses the same things, whatever the way.
"""

from __future__ import annotations

import atexit
import json
import os
import resource
import sys
from collections.abc import Iterable, Sequence
from typing import Any, Optional

#: How every refusal's message begins (the grader finds them in the report).
REFUSED = "refused by the grading sandbox"
#: The environment variable that carries the settings.
ENV = "OMTP_GUARD"

_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND
_PATH_EVENTS = {
    "os.mkdir": (0,),
    "os.rmdir": (0,),
    "os.remove": (0,),
    "os.rename": (0, 1),
    "os.link": (1,),
    "os.symlink": (1,),
    "os.truncate": (0,),
    "os.chmod": (0,),
    "os.chown": (0,),
    "os.utime": (0,),
    "shutil.rmtree": (0,),
}
_NETWORK_EVENTS = ("socket.connect", "socket.sendto", "socket.sendmsg", "socket.bind")


def set_limits(limits: dict[str, Any], *, in_namespace: bool) -> None:
    """The rlimits of ``limits`` (see :class:`omtp_drake.grading.isolation.Limits`) on this process."""
    memory = int(limits["memory_mb"]) << 20
    cpu = int(limits["cpu_s"])
    resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 2))  # SIGXCPU, then SIGKILL
    files = int(limits["open_files"])
    resource.setrlimit(resource.RLIMIT_NOFILE, (files, files))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    if in_namespace:  # elsewhere RLIMIT_NPROC counts every process of the user
        procs = int(limits["processes"])
        resource.setrlimit(resource.RLIMIT_NPROC, (procs, procs))


def _die_with_parent(parent: int) -> None:
    """SIGKILL when the parent (the grader's worker) dies; exits now if it is gone already."""
    import ctypes
    import signal

    pr_set_pdeathsig = 1
    ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent:
        os._exit(137)


class Records:
    """The guard's records for the grader: JSON lines appended to the file at ``path``
    (created with the first record, inside the run's folder; none: dropped)."""

    def __init__(self, path: Optional[str]):
        self.path = path
        self._fd = -1

    def add(self, **record: Any) -> None:
        if not self.path:
            return
        try:
            if self._fd < 0:
                self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
            os.write(self._fd, (json.dumps(record) + "\n").encode())
        except OSError:
            pass  # the run's folder is gone or full: the grader goes without


def read_records(path: str | os.PathLike[str]) -> list[dict[str, Any]]:
    """The records a run's guard kept at ``path`` (none when it wrote none)."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError:
        return []
    records = []
    for line in lines:
        try:
            records.append(json.loads(line))
        except ValueError:
            continue  # a line cut by the run's death
    return records


class Guard:
    """The audit hook (see the module doc); ``armed`` once the script's code runs."""

    def __init__(self, writable: Sequence[str], script: str, records: Optional[Records] = None):
        self.writable = [os.path.realpath(p) for p in writable] + ["/dev/null"]
        self.script = os.path.realpath(script)
        self.armed = False
        self.session = os.getsid(0)
        self.ancestors = _ancestors()
        self.records = records or Records(None)

    def _inside(self, path: Any) -> bool:
        if isinstance(path, int):
            return True  # a descriptor: already open
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        real = os.path.realpath(os.fspath(path))
        return any(real == w or real.startswith(w.rstrip("/") + "/") for w in self.writable)

    def _refuse(self, event: str, what: str) -> None:
        self.records.add(refused=event, what=what)
        raise PermissionError(f"{REFUSED}: {what}")

    def __call__(self, event: str, args: tuple) -> None:
        if not self.armed:
            if event == "exec" and getattr(args[0], "co_filename", None) == self.script:
                self.armed = True
            return
        if event == "open":
            path, mode, flags = args
            writes = any(c in (mode or "") for c in "wax+") if isinstance(mode, str) else False
            writes = writes or bool((flags or 0) & _WRITE_FLAGS)
            if writes and path is not None and not self._inside(path):
                self._refuse(event, f"write to {os.fsdecode(path)} (outside the script's folder)")
        elif event in _PATH_EVENTS:
            for i in _PATH_EVENTS[event]:
                if i < len(args) and args[i] is not None and not self._inside(args[i]):
                    self._refuse(
                        event, f"{event.split('.')[-1]} {os.fsdecode(args[i])} (outside the script's folder)"
                    )
        elif event in _NETWORK_EVENTS:
            self._refuse(event, f"network {event.split('.')[-1]} to {args[1]!r}")
        elif event in ("os.kill", "os.killpg"):
            self._check_signal(event, int(args[0]))

    def _check_signal(self, event: str, pid: int) -> None:
        if event == "os.killpg" or pid < 0:
            target = abs(pid)
            ok = target == 0 or target == os.getpgid(0)
        else:
            try:
                ok = pid == 0 or (pid not in self.ancestors and os.getsid(pid) == self.session)
            except OSError:
                ok = True  # no such process: the kernel answers
        if not ok:
            self._refuse(event, f"signal to process {pid} (not one of the script's processes)")


def process_table() -> dict[int, tuple[int, int, int]]:
    """pid -> (parent pid, session id, start time) of every process but zombies (from /proc)."""
    table = {}
    for name in os.listdir("/proc"):
        if name.isdigit() and (entry := _stat(name)) is not None:
            table[int(name)] = entry
    return table


def _stat(pid: str) -> Optional[tuple[int, int, int]]:
    """(parent pid, session id, start time) of the process ``pid``; None when it is gone or a zombie."""
    try:
        fd = os.open(f"/proc/{pid}/stat", os.O_RDONLY)
    except OSError:
        return None
    try:
        stat = os.read(fd, 4096)
    except OSError:
        return None
    finally:
        os.close(fd)
    fields = stat[stat.rfind(b")") + 2 :].split(None, 20)
    return None if not fields or fields[0] == b"Z" else (int(fields[1]), int(fields[3]), int(fields[19]))


class ProcessScan:
    """:func:`process_table` for a watcher that looks often (every 50 ms, for the whole of a run):
    each look lists /proc, reads the processes it has not read before and those of ``ours``,
    and keeps the first reading of the others. A process that was not one of a run's when
    first read never becomes one (a run's processes are born to it, or in its session, and
    ``setsid`` only leaves a session), so its parent and session need no second reading;
    a full table read each look cost the grader's worker about 3 ms, some 6 % of a core
    per run under way."""

    def __init__(self) -> None:
        self._others: dict[int, tuple[int, int, int]] = {}

    def table(self, ours: Iterable[int]) -> dict[int, tuple[int, int, int]]:
        """The table now; ``ours``: the pids whose entries are read again (the run's, seen so far)."""
        again = set(ours)
        table: dict[int, tuple[int, int, int]] = {}
        for name in os.listdir("/proc"):
            if not name.isdigit():
                continue
            pid = int(name)
            entry = self._others.get(pid) if pid not in again else None
            if entry is None and (entry := _stat(name)) is None:
                continue
            table[pid] = entry
        return table

    def remember_others(self, table: dict[int, tuple[int, int, int]], ours: Iterable[int]) -> None:
        """Keeps ``table``'s entries but ``ours`` (the run's processes in it) as not the run's."""
        mine = set(ours)
        self._others = {p: e for p, e in table.items() if p not in mine}


def descendants(roots: Iterable[int], table: dict[int, tuple[int, int, int]]) -> set[int]:
    """The pids below ``roots`` in ``table`` (:func:`process_table`): children, their children..."""
    found: set[int] = set()
    level = set(roots)
    while level:
        level = {p for p, (ppid, _, _) in table.items() if ppid in level} - found
        found |= level
    return found


def _record_exit(records: Records) -> None:
    """Records an exception nothing caught, and at this process's exit how many processes
    it leaves running."""
    from omtp_drake.errors import exception_kind

    previous = sys.excepthook

    def uncaught(kind: type[BaseException], value: BaseException, tb: Any) -> None:
        records.add(uncaught=exception_kind(value))
        previous(kind, value, tb)

    sys.excepthook = uncaught
    atexit.register(lambda: records.add(left_running=len(descendants([os.getpid()], process_table()))))


def _ancestors() -> set[int]:
    """The pids of this process's parent, its parent's parent... (the grader, bubblewrap's init)."""
    found: set[int] = set()
    pid = os.getppid()
    while pid > 0 and pid not in found:
        found.add(pid)
        try:
            with open(f"/proc/{pid}/stat", "rb") as f:
                stat = f.read()
        except OSError:
            break
        pid = int(stat[stat.rfind(b")") + 2 :].split()[1])
    return found


def install_from_env() -> None:
    """Limits and guard of ``$OMTP_GUARD``'s settings on this process (nothing when it is unset)."""
    raw = os.environ.get(ENV)
    if not raw:
        return
    settings = json.loads(raw)
    if settings.get("parent"):  # inside bubblewrap, its --die-with-parent does it
        _die_with_parent(int(settings["parent"]))
    set_limits(settings["limits"], in_namespace=bool(settings.get("in_namespace")))
    records = Records(settings.get("records"))
    _record_exit(records)
    sys.addaudithook(Guard(settings["writable"], settings["script"], records))
