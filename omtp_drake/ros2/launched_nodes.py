"""The workspace's own ROS 2 nodes a launch file starts, run beside the cell as ``ros2 launch``
runs them: each its own process (``python`` of this environment, the network's variables),
its output shown line by line as ``[NAME-N] line``, its end said in one line when it comes;
when the run ends, the nodes still running get SIGINT, then SIGTERM after 5 s, then SIGKILL
after 5 s more (``ros2 launch``'s shutdown). Which nodes start and with which command line is
decided in :mod:`omtp_drake.launch.ros2_nodes`; this module only runs them.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from omtp_drake.launch.ros2_nodes import Ros2NodeProgram

#: Seconds a node gets after SIGINT, then after SIGTERM (``ros2 launch``'s sigterm_timeout
#: and sigkill_timeout).
GRACE_S = 5.0


def _sigint_as_at_a_terminal() -> None:
    """In the child before its program starts: SIGINT at its default, as ``ros2 launch``'s nodes
    get it (launch catches SIGINT, and a caught signal is reset to its default by exec). An
    ignored one is inherited as ignored: a caller started in the background of a shell (``cmd &``
    without job control ignores SIGINT), e.g. pytest in a ``pytest ... &`` run, would give every
    node an ignored SIGINT, Python would then install no KeyboardInterrupt handler, and each node
    would skip its Ctrl-C cleanup and be killed by the SIGTERM that follows. (``omtp-drake ros2``
    catches SIGINT itself while its nodes run, so there they got the default already.)"""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(
    program: Ros2NodeProgram,
    argv: Sequence[str],
    label: str,
    env: Mapping[str, str],
    say: Callable[[str], None],
) -> tuple[subprocess.Popen, threading.Thread]:
    environment = dict(env)
    if program.pythonpath is not None:
        environment["PYTHONPATH"] = os.pathsep.join(
            p for p in (str(program.pythonpath), environment.get("PYTHONPATH", "")) if p
        )
    command = [*program.command(sys.executable), *argv]
    process = subprocess.Popen(
        command,
        env=environment,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        process_group=0,  # Ctrl-C reaches the run only; it passes it on, as ros2 launch does
        preexec_fn=_sigint_as_at_a_terminal,
    )
    say(f"[{label}] started [pid {process.pid}]: {shlex.join(command)}")
    reader = threading.Thread(target=_relay, args=(process, label, say), daemon=True)
    reader.start()
    return process, reader


def _relay(process: subprocess.Popen, label: str, say: Callable[[str], None]) -> None:
    """The node's lines, then its end (when it comes, not only when the run ends)."""
    for line in process.stdout or ():
        say(f"[{label}] {line.rstrip()}")
    code = process.wait()
    if code == 0:
        say(f"[{label}] finished cleanly [pid {process.pid}]")
    else:
        say(f"[{label}] died [pid {process.pid}, exit code {code}]")


def _stop(process: subprocess.Popen) -> None:
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
        if process.poll() is not None:
            return
        process.send_signal(sig)
        with contextlib.suppress(subprocess.TimeoutExpired):
            process.wait(timeout=GRACE_S)


@contextlib.contextmanager
def launched_nodes(
    nodes: Sequence[tuple[Ros2NodeProgram, Sequence[str]]], env: Mapping[str, str], say: Callable[[str], None]
) -> Iterator[None]:
    """Runs ``nodes`` (a program and its arguments each) while the block runs, in ``env``."""
    running: list[tuple[subprocess.Popen, threading.Thread]] = []
    try:
        for i, (program, argv) in enumerate(nodes, 1):
            running.append(_start(program, argv, f"{program.name}-{i}", env, say))
        yield
    finally:
        for process, _ in running:
            _stop(process)
        for _, reader in running:
            reader.join()
