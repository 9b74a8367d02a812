"""How ``omtp-drake ros2`` runs a launch's own nodes (omtp_drake.ros2.launched_nodes), without
DDS: lines relayed with the process's label, its end said when it comes, and at the end of
the run SIGINT, then SIGTERM, then SIGKILL for a node that will not stop."""

from __future__ import annotations

import os
import signal
import textwrap
import time

import pytest

from omtp_drake.launch.ros2_nodes import Ros2NodeProgram, console_scripts, find_program
from omtp_drake.ros2 import launched_nodes as module
from omtp_drake.ros2.launched_nodes import launched_nodes


def _program(tmp_path, name: str, body: str) -> Ros2NodeProgram:
    path = tmp_path / f"{name}.py"
    path.write_text(textwrap.dedent(body))
    return Ros2NodeProgram(name, path)


def _run(nodes, *wait_for: str) -> list[str]:
    """The lines of running ``nodes`` until each of ``wait_for`` is in one of them."""
    lines: list[str] = []
    with launched_nodes(nodes, dict(os.environ), lines.append):
        while not all(any(part in line for line in lines) for part in wait_for):
            time.sleep(0.01)
    return lines


def test_lines_are_relayed_and_a_node_ending_by_itself_is_said_at_once(tmp_path):
    talker = _program(tmp_path, "talker", "import sys\nprint('hello', sys.argv[1:])\n")
    failing = _program(tmp_path, "failing", "raise SystemExit(3)\n")
    lines = _run(
        [(talker, ["--ros-args", "-p", "a:=1"]), (failing, [])], "[failing-2] died", "[talker-1] finished"
    )
    assert "[talker-1] hello ['--ros-args', '-p', 'a:=1']" in lines
    assert any(line.startswith("[talker-1] finished cleanly [pid ") for line in lines)
    assert any(line.startswith("[failing-2] died [pid ") and line.endswith("exit code 3]") for line in lines)


def test_the_run_ending_stops_each_node_sigint_first_then_sigterm(tmp_path, monkeypatch):
    # Each grace is waited out only by a node that does not stop (stubborn: 1 s of this test); the
    # polite one needs milliseconds. (Its failures at load 9, once blamed on a 0.5 s grace, were
    # pytest's ignored SIGINT passed on to the nodes: run in the background, 'pytest ... &'.)
    monkeypatch.setattr(module, "GRACE_S", 1.0)
    polite = _program(
        tmp_path,
        "polite",
        """
        import time
        try:
            print('up', flush=True)
            while True:
                time.sleep(0.05)
        except KeyboardInterrupt:
            print('stopping on Ctrl-C', flush=True)
        """,
    )
    stubborn = _program(
        tmp_path,
        "stubborn",
        """
        import signal, time
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        print('up', flush=True)
        while True:
            time.sleep(0.05)
        """,
    )
    # Run as from 'pytest ... &' (a shell's background job ignores SIGINT): each node still gets
    # SIGINT at its default, as ros2 launch's nodes do, and its Ctrl-C handler runs.
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        lines = _run([(polite, []), (stubborn, [])], "[polite-1] up", "[stubborn-2] up")
    finally:
        signal.signal(signal.SIGINT, previous)
    assert "[polite-1] stopping on Ctrl-C" in lines
    assert any(line.startswith("[polite-1] finished cleanly") for line in lines)
    assert any(line.startswith("[stubborn-2] died") and line.endswith("exit code -15]") for line in lines)


def test_console_scripts_come_from_setup_py_and_setup_cfg(tmp_path):
    (tmp_path / "setup.py").write_text(
        "from setuptools import setup\n"
        "setup(name='p', entry_points={'console_scripts': ['talk = p.talker:main', 'hear=p.listener:run']})\n"
    )
    (tmp_path / "setup.cfg").write_text("[options.entry_points]\nconsole_scripts =\n    echo = p.echo:main\n")
    assert console_scripts(tmp_path) == {
        "talk": "p.talker:main",
        "hear": "p.listener:run",
        "echo": "p.echo:main",
    }
    (tmp_path / "p").mkdir()
    (tmp_path / "p" / "talker.py").write_text("def main():\n    return 0\n")
    program = find_program(tmp_path, "talk")
    assert program == Ros2NodeProgram("talk", tmp_path / "p" / "talker.py", "p.talker:main", tmp_path)
    assert find_program(tmp_path, "compiled_node") is None


def test_a_console_script_whose_module_is_missing_is_one_error(tmp_path):
    (tmp_path / "setup.py").write_text("setup(entry_points={'console_scripts': ['talk = p.talker:main']})\n")
    with pytest.raises(
        Exception, match=r"setup.py: console script talk = p.talker:main: no file .*talker.py"
    ):
        find_program(tmp_path, "talk")
