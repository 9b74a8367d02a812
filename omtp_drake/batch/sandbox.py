"""A run in isolation: a runner subprocess per worker thread that forks one child per run.

A worker never runs a simulation itself. Each worker thread owns a *runner*
subprocess (started once, with omtp_drake imported) that forks one child per
run, so a run that raises, hangs past its timeout (the runner kills it) or dies
of a signal (a segfault in Drake, ``os.abort()``) costs only its child: the
answer is a status ``error``, ``timeout`` or ``crashed`` with its message
(:mod:`omtp_drake.batch.cluster` records it and retries the run once on another
worker). A child per run also means no state carries over between runs: a
run's result depends only on its scenario and seed.
"""

from __future__ import annotations

import logging
import os
import pickle
import select
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NoReturn, Optional

from omtp_drake.batch.run_records import CRASHED, ERROR, FINISHED, TIMEOUT
from omtp_drake.batch.sweep import RunSpec
from omtp_drake.errors import describe_exception

if TYPE_CHECKING:
    from omtp_drake.scenario import Scenario
    from omtp_drake.tasks.run import TaskResult

#: A run's function: (the prepared scenario, the duration or None) -> its result.
#: The default is :func:`simulate`; tests inject faulty ones (see ``run_batch``).
RunFunction = Callable[["Scenario", Optional[float]], "TaskResult"]

#: Seconds a runner may take to start (import omtp_drake) on a loaded machine.
_RUNNER_START_TIMEOUT_S = 300.0
#: Extra seconds the worker waits for its runner after a run's timeout.
_RUNNER_GUARD_S = 30.0


def simulate(scenario: Scenario, duration: Optional[float]) -> TaskResult:
    """The default run function: the scenario's task (:func:`run_task`)."""
    from omtp_drake.tasks.run import run_task

    return run_task(scenario, duration=duration)


def run_in_child(spec: RunSpec, duration: Optional[float], run_fn: RunFunction) -> TaskResult:
    """What a forked child runs: ``run_fn`` on the run's scenario (built in the child)."""
    return run_fn(spec.scenario(), duration)


def _write_frame(fd: int, obj: Any) -> None:
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    view = memoryview(struct.pack("!Q", len(data)) + data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exact(fd: int, n: int, deadline: Optional[float]) -> bytes:
    chunks, left = [], n
    while left:
        if deadline is not None:
            wait = deadline - time.monotonic()
            if wait <= 0 or not select.select([fd], [], [], wait)[0]:
                raise TimeoutError("no answer in time")
        chunk = os.read(fd, min(left, 1 << 20))
        if not chunk:
            raise EOFError("the pipe closed")
        chunks.append(chunk)
        left -= len(chunk)
    return b"".join(chunks)


def _read_frame(fd: int, deadline: Optional[float] = None) -> Any:
    (n,) = struct.unpack("!Q", _read_exact(fd, 8, deadline))
    return pickle.loads(_read_exact(fd, n, deadline))


def _runner_main() -> None:
    """The runner subprocess: reads runs from stdin, forks a child for each,
    enforces its timeout, answers on stdout (see :class:`Sandbox`)."""
    in_fd, out_fd = os.dup(0), os.dup(1)
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    os.dup2(2, 1)  # stray prints go to stderr, not into the protocol
    hello = _read_frame(in_fd)
    sys.path[:] = hello["sys_path"]
    # Preloaded once: every forked child starts with pydrake and omtp_drake imported.
    import pydrake.common  # noqa: F401

    import omtp_drake.tasks.run  # noqa: F401

    logging.getLogger("drake").setLevel(logging.ERROR)
    _write_frame(out_fd, {"ready": os.getpid()})
    while True:
        try:
            request = _read_frame(in_fd)
        except EOFError:
            return
        _write_frame(out_fd, _fork_and_run(request["payload"], request["timeout"], in_fd))


def _fork_and_run(payload: bytes, timeout: Optional[float], watch_fd: int) -> dict[str, Any]:
    """Runs the pickled (function, args) in a forked child; kills it at the
    timeout, or (and exits) when ``watch_fd`` closes (the worker is gone)."""
    with tempfile.TemporaryFile() as err:
        r, w = os.pipe()
        start = time.monotonic()
        pid = os.fork()
        if pid == 0:
            _child(payload, r, w, err.fileno())
        os.close(w)
        chunks: list[bytes] = []
        timed_out = False
        deadline = None if timeout is None else start + timeout
        while True:
            wait = None if deadline is None else max(0.0, deadline - time.monotonic())
            ready = select.select([r, watch_fd], [], [], wait)[0]
            if not ready:
                timed_out = True
                os.kill(pid, signal.SIGKILL)
                break
            if watch_fd in ready:  # the worker never writes while waiting: it is gone
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                os._exit(0)
            chunk = os.read(r, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
        os.close(r)
        _, status = os.waitpid(pid, 0)
        wall = time.monotonic() - start
        if timed_out:
            return {"status": TIMEOUT, "message": f"exceeded the timeout of {timeout:g} s wall (killed)"}
        try:
            reply = pickle.loads(b"".join(chunks))
            reply["wall"] = wall
            return reply
        except Exception:  # no complete answer: the child died
            if os.WIFSIGNALED(status):
                sig = os.WTERMSIG(status)
                name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
                what = f"the run's process died of {name}"
            else:
                what = f"the run's process exited with code {os.waitstatus_to_exitcode(status)}"
            tail = _tail(err)
            return {"status": CRASHED, "message": what + (f"; its last output: {tail}" if tail else "")}


def _tail(f: Any, limit: int = 600) -> str:
    """The last lines of a file (a child's stderr), as one line."""
    f.seek(0, os.SEEK_END)
    size = f.tell()
    f.seek(max(0, size - limit))
    lines = [ln.strip() for ln in f.read().decode(errors="replace").splitlines() if ln.strip()]
    return " | ".join(lines[-4:])


def _child(payload: bytes, r: int, w: int, err_fd: int) -> NoReturn:
    """The forked child of one run: never returns."""
    code = 0
    try:
        os.close(r)
        os.dup2(err_fd, 2)
        os.dup2(err_fd, 1)
        try:
            fn, args = pickle.loads(payload)
            reply: dict[str, Any] = {"status": FINISHED, "value": pickle.dumps(fn(*args)), "message": ""}
        except BaseException as e:  # every failure of a run is recorded, whatever it is
            reply = {"status": ERROR, "value": None, "message": describe_exception(e)}
        data = memoryview(pickle.dumps(reply))
        while data:
            data = data[os.write(w, data) :]
    except BaseException:
        code = 1
    finally:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:
                pass
        os._exit(code)


class Sandbox:
    """A runner subprocess (started on first use, restarted if it dies) that runs
    each call in a forked child: a crash or hang costs the child, not the worker."""

    def __init__(self) -> None:
        self._proc: Optional[subprocess.Popen] = None

    def _start(self) -> subprocess.Popen:
        env = dict(os.environ)
        for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            env.setdefault(var, "1")  # one core per run: the workers are the parallelism
        proc = subprocess.Popen(
            [sys.executable, "-c", "from omtp_drake.batch.sandbox import _runner_main; _runner_main()"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            bufsize=0,
            env=env,
        )
        assert proc.stdin is not None and proc.stdout is not None
        try:
            _write_frame(proc.stdin.fileno(), {"sys_path": list(sys.path)})
            _read_frame(proc.stdout.fileno(), time.monotonic() + _RUNNER_START_TIMEOUT_S)
        except (EOFError, OSError, TimeoutError) as e:
            proc.kill()
            proc.wait()
            raise RuntimeError(f"the run sandbox did not start ({e})") from None
        return proc

    def stop(self) -> None:
        if self._proc is not None:
            self._proc.kill()
            self._proc.wait()
            self._proc = None

    def call(self, fn: Callable[..., Any], args: tuple, timeout: Optional[float]) -> dict[str, Any]:
        """{status, message, value (the pickled return value), wall} of ``fn(*args)``."""
        import cloudpickle

        payload = cloudpickle.dumps((fn, args))  # by value for notebook functions
        if self._proc is None or self._proc.poll() is not None:
            self._proc = self._start()
        proc = self._proc
        assert proc.stdin is not None and proc.stdout is not None
        deadline = None if timeout is None else time.monotonic() + timeout + _RUNNER_GUARD_S
        try:
            _write_frame(proc.stdin.fileno(), {"payload": payload, "timeout": timeout})
            return _read_frame(proc.stdout.fileno(), deadline)
        except (EOFError, OSError, TimeoutError) as e:
            self.stop()
            return {"status": CRASHED, "message": f"the run sandbox died ({e})"}


_SANDBOXES = threading.local()


def thread_sandbox() -> Sandbox:
    """This thread's sandbox."""
    if not hasattr(_SANDBOXES, "sandbox"):
        _SANDBOXES.sandbox = Sandbox()
    return _SANDBOXES.sandbox
