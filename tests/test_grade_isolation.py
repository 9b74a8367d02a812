"""``grade`` on a hostile class: every script gets its own verdict, the honest ones are graded,
no process outlives the run and no file appears outside, with and without bubblewrap."""

import contextlib
import csv
import glob
import json
import os
import signal
import socket
import tempfile
import textwrap
import uuid
from dataclasses import asdict
from pathlib import Path

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.grading.cli import main
from omtp_drake.grading.grade import grade_folder, grading_client
from omtp_drake.grading.isolation import Limits, bwrap_works

SCENARIO = "lecture6_assignment3"
#: The scenario of the runs whose verdicts need no cell (all but the killer's honest one): the
#: floor alone. A run's start-up on it costs 1.4-1.5 CPU s against 1.9-2.3 s on SCENARIO, and
#: the spinner's simulated seconds cost next to nothing (measured back to back, ros-run, load 8).
EMPTY_CELL = 'description: "the floor alone: a run whose verdict needs no cell"\nseed: 0\n'
#: Limits the hogs hit at once, far from what a script of the class needs, however slow or busy
#: the machine: a run of the class on lecture6_assignment3 took 1.0-1.7 CPU s (start-up; measured
#: at load 4-8: the spinner 1.4-1.7 to its 3 s timeout, the output flood's 6 MB in long lines
#: 1.3-1.5, os._exit's 1.0-1.2; at load 12 the spinner took 2.5), on EMPTY_CELL about 0.5 s less;
#: the CPU limit is 4 (over 2x: CPU seconds do not grow with a busy machine, only with a slower
#: one); the busy loop reaches it whatever the machine's share of a core, long before
#: WALL_TIMEOUT. Each CPU second of the busy loop is a second of this test.
LIMITS = Limits(memory_mb=1024, processes=12, cpu_s=4, open_files=256, output_kb=64)
#: Simulated seconds per run: the spinner reaches it at a small CPU cost (~0.1 CPU s per
#: simulated s).
TIMEOUT = 3.0
#: Wall seconds per run: a bound no script of the hostile class reaches by itself (the one
#: verdict that needs a wall timeout has its own test, with its own short one).
WALL_TIMEOUT = 300.0

SANDBOXES = [
    "none",
    pytest.param(
        "bwrap", marks=pytest.mark.skipif(not bwrap_works(), reason="bubblewrap does not work here")
    ),
]


@pytest.fixture(scope="module")
def empty_cell(tmp_path_factory) -> str:
    """The path of EMPTY_CELL's scenario file (its folder is readable inside bubblewrap)."""
    path = tmp_path_factory.mktemp("scenario") / "empty_cell.yaml"
    path.write_text(EMPTY_CELL)
    return str(path)


@pytest.fixture(scope="module")
def client():
    """The module's grading cluster: two workers, started once (a cluster of its own per grade
    cost each test about 1.5 CPU s and a few wall seconds)."""
    with grading_client(2) as shared:
        yield shared


#: The scripts whose verdict comes the same way in either sandbox, graded without bubblewrap
#: only: from the run's report or its exit code (spinner, os_exit), the guard's limits in the
#: run's own process (memory_hog; busy_loop's SIGXCPU, whose 128 + signal exit status of
#: bubblewrap's is self_signal's there), the grader's pipes (output_flood). The rest meet the
#: namespace's process limit and init (fork_sleepers, leaves_children, trespasser: its parent
#: is the init; the guard's audit hook refuses its connection and write before the kernel
#: would, the kernel's refusals are test_bubblewrap_refuses_what_gets_past_the_guard's) or
#: bubblewrap's exit status (self_signal) there. Each run costs 1-1.5 CPU s, busy_loop 4.
SANDBOX_ALIKE = ("spinner.py", "memory_hog.py", "output_flood.py", "busy_loop.py", "os_exit.py")


def hostile_class(folder: Path, tag: str, port: int, sandbox: str = "none") -> dict[str, str]:
    """The class folder: script name -> the verdict it must get (in bubblewrap, all but
    SANDBOX_ALIKE). ``tag`` names the files the scripts try to leave behind (outside their
    folder) and their sleeping children."""
    scripts = {
        # A student who loops forever waiting for something, without sleeping.
        "busy_loop.py": ("import rospy\nrospy.init_node('busy')\nwhile True:\n    pass\n", "cpu limit"),
        "spinner.py": ("import rospy\nrospy.init_node('spinner')\nrospy.spin()\n", "simulated timeout"),
        # The limit is on address space: calloc'd bytes reach it untouched (a bytearray's
        # zeroing of the same GB cost 0.85 CPU s more).
        "memory_hog.py": ("hog = []\nwhile True:\n    hog.append(bytes(50 * 1024 * 1024))\n", "memory limit"),
        "fork_sleepers.py": (
            f"""
            import os, time
            for i in range(40):
                if os.fork() == 0:
                    os.execvp("sleep", ["{tag}", "300"])
            time.sleep(600)
            """,
            "process limit",
        ),
        "leaves_children.py": (
            f"""
            import os, subprocess
            for i in range(2):
                subprocess.Popen(["{tag}", "301"], executable="sleep")
            print("forked", flush=True)
            """,
            "ok",
        ),
        # Each of the guard's refusals in turn, the last uncaught: a connection, a signal to its
        # parent (in bubblewrap, the namespace's init), a write outside its folder.
        "trespasser.py": (
            f"""
            import os, signal, socket
            import rospy
            rospy.init_node("trespasser")
            try:
                socket.create_connection(("127.0.0.1", {port}), timeout=2).sendall(b"hi")
            except OSError as e:
                print("network:", e)
            try:
                os.kill(os.getppid(), signal.SIGKILL)
            except OSError as e:
                print("kill:", e)
            with open("/var/tmp/escape_{tag}.txt", "w") as f:
                f.write("I was here")
            """,
            "exception",
        ),
        "os_exit.py": ("import os\nprint('leaving', flush=True)\nos._exit(0)\n", "exited early"),
        # 6 MB in 600 long lines: 200000 short ones cost 2-2.5 CPU s more (the script's and
        # the grader's), and a CPU limit that had to stay 2x above them.
        "output_flood.py": ("for i in range(600):\n    print('spam ' * 2000, i)\n", "output cut"),
        "self_signal.py": ("import os, signal\nos.kill(os.getpid(), signal.SIGSEGV)\n", "killed by signal"),
    }
    if sandbox == "none":  # a script that looks at its folder's copy and writes in it
        scripts["alice.py"] = (LOOKER, "ok")
        (folder / "data.csv").write_text("1,2\n")
        (folder / "_helpers.py").write_text("GREETING = 'hello'\n")
        (folder / "grade.yaml").write_text("alice.py:\n  moveit: noetic\n")
    # An honest script's row (ok, and its stdout) has its own test in each sandbox: the one
    # graded after the killer (test_a_script_that_kills_its_worker_is_its_own_row[none]), the
    # bypass's (test_bubblewrap_refuses_what_gets_past_the_guard); an
    # exception's message with its line is trespasser's here (test_ros_grade's bob too).
    if sandbox == "bwrap":
        scripts = {name: script for name, script in scripts.items() if name not in SANDBOX_ALIKE}
    for name, (text, _) in scripts.items():
        (folder / name).write_text(textwrap.dedent(text).lstrip())
    return {name: verdict for name, (_, verdict) in scripts.items()}


#: Sees its own copy of the class folder only: its helper module and data, not the other
#: scripts, grade.yaml or the results folder inside the class folder; writes in its copy.
LOOKER = """
import os
from _helpers import GREETING
print(GREETING, sorted(os.listdir('.')))
open('notes.txt', 'w').write('mine')
"""


def processes_with(tag: str) -> list[int]:
    """Live processes whose command line holds ``tag``."""
    found = []
    for entry in os.scandir("/proc"):
        if entry.name.isdigit():
            try:
                cmdline = Path(entry.path, "cmdline").read_bytes()
                state = Path(entry.path, "stat").read_text().rsplit(")", 1)[1].split()[0]
            except OSError:
                continue
            if tag.encode() in cmdline and state != "Z":
                found.append(int(entry.name))
    return found


@pytest.mark.parametrize("sandbox", SANDBOXES)
def test_a_hostile_class_gets_one_verdict_per_script_and_leaves_nothing(
    tmp_path, sandbox, client, empty_cell
):
    folder = tmp_path / "class"
    folder.mkdir()
    tag = f"omtp-hostile-{uuid.uuid4().hex[:8]}"
    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(0.1)
    expected = hostile_class(folder, tag, listener.getsockname()[1], sandbox)
    out = folder / "results"  # inside the class folder: never copied
    grades = grade_folder(
        folder, empty_cell, timeout=TIMEOUT, wall_timeout=WALL_TIMEOUT, out=out, limits=LIMITS,
        sandbox=sandbox, client=client,
    )  # fmt: skip
    by_name = {g.script: g for g in grades}
    assert {name: g.status for name, g in by_name.items()} == expected
    # What the sandbox refused, in the script's row; the exception names the script's line.
    trespasser = by_name["trespasser.py"]
    assert f"write to /var/tmp/escape_{tag}.txt" in trespasser.refused
    assert "network connect" in trespasser.refused and "signal to process" in trespasser.refused
    assert trespasser.message.startswith("PermissionError: ")
    assert trespasser.message.endswith(" (at trespasser.py:12 in <module>)"), trespasser.message
    if sandbox == "none":
        assert by_name["os_exit.py"].message.startswith("exited early with code 0")
    # Children left behind are killed, and say so; the run did not wait for their pipes (they
    # sleep 301 s, past the wall timeout: its verdict would be "wall timeout").
    assert "2 process(es) left running, killed" in by_name["leaves_children.py"].message
    # Output: the first 64 KB kept in a file, the rest counted.
    if sandbox == "none":
        flood = by_name["output_flood.py"].isolation["stdout"]
        assert flood["kept"] == 64 * 1024 and flood["cut"] > 5_000_000
        assert (out / "runs" / "output_flood.stdout.txt").stat().st_size == 64 * 1024
    # A script sees its own copy of the folder only, and writes in it.
    if sandbox == "none":
        seen = (out / "runs" / "alice.stdout.txt").read_text().splitlines()[0]
        assert seen == "hello ['.tmp', '_helpers.py', 'alice.py', 'data.csv']"
        assert not (folder / "notes.txt").exists()
    # No process, no file, no connection outside.
    assert processes_with(tag) == []
    assert not Path(f"/var/tmp/escape_{tag}.txt").exists()
    with pytest.raises(TimeoutError):
        listener.accept()
    listener.close()
    # The table, the CSV and the plot are written; the limits and sandbox are in each report.
    rows = list(csv.DictReader(open(out / "grades.csv")))
    assert [r["status"] for r in rows] == [g.status for g in grades]
    assert (out / "grades.png").stat().st_size > 1000
    run = json.loads((out / "runs" / "trespasser.json").read_text())
    assert run["isolation"]["sandbox"] == sandbox and run["isolation"]["limits"]["memory_mb"] == 1024


@pytest.mark.parametrize("sandbox", SANDBOXES)
def test_a_script_sleeping_in_wall_time_gets_the_wall_timeout(tmp_path, sandbox, client, empty_cell):
    """time.sleep: wall time, not simulated time (the course's classic mistake). The script
    sleeps far longer than the wall timeout, however fast the machine. The wall timeout is
    short (its verdict comes first, whatever the run was doing when it was reached): each of
    its seconds is a second of this test."""
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "wall_sleeper.py").write_text("import time\ntime.sleep(600)\n")
    out = tmp_path / "out"
    (grade,) = grade_folder(folder, empty_cell, wall_timeout=2.0, out=out, sandbox=sandbox, client=client)
    assert grade.status == "wall timeout" and grade.message == "over 2 s wall time (killed)"
    assert grade.report is None and grade.isolation["timed_out"]


#: A script that waits in simulated time, then prints it (on the floor: the killer's honest
#: classmate; lecture 6's example there cost 0.5 CPU s more, and a build of its cell here).
HONEST = """
import rospy
rospy.init_node("honest")
rospy.sleep(1.6)
print("honest at %.2f" % rospy.get_time())
"""


#: Gets past the guard (ctypes) to kill the grader's worker, after starting a sleeping child;
#: where the kill did nothing (its parent is bubblewrap's init) it says so and fails.
WORKER_KILLER = """
import ctypes, os, subprocess, time
subprocess.Popen(["{tag}", "300"], executable="sleep")
time.sleep(0.5)
ctypes.CDLL(None).kill(os.getppid(), 9)
time.sleep(1.0)
raise RuntimeError("still here after killing my parent")
"""


@pytest.mark.parametrize("sandbox", SANDBOXES)
def test_a_script_that_kills_its_worker_is_its_own_row(tmp_path, sandbox, client, empty_cell):
    folder = tmp_path / "class"
    folder.mkdir()
    tag = f"omtp-killer-{uuid.uuid4().hex[:8]}"
    killer_name = f"a_killer_{sandbox}"  # its own temp folders' names: the other sandbox's run may be on
    (folder / f"{killer_name}.py").write_text(WORKER_KILLER.format(tag=tag))
    if sandbox == "none":  # graded after the killer, on the worker started again
        (folder / "b_honest.py").write_text(HONEST)
    # The wall timeout, far past the honest run's time: 1.6 s alone, 3.9 s pinned to one core
    # beside a busy loop (taskset -c 0), about 5 s beside the rest of the suite (-n 2): 15 s is
    # 1.5x that on a machine twice as slow. The killer's kill comes about 1 s after its start.
    # No sandbox: a cluster of its own, of one worker: the honest script runs after the killer,
    # on the worker started again in place of the one killed. Bubblewrap: its init, not the
    # worker, is the killer's parent, so the module's cluster (a new one costs about 2 CPU s)
    # and the killer alone, on the floor (an honest row in bubblewrap, ok with its stdout, is
    # test_bubblewrap_refuses_what_gets_past_the_guard's; on this scenario test_grade_cache's);
    # a kill that got through would make the killer's row "worker died" (its nanny starts the
    # worker again for the next test).
    own = {"workers": 1} if sandbox == "none" else {"client": client}
    grades = grade_folder(folder, empty_cell, wall_timeout=15.0, out=tmp_path / "out", sandbox=sandbox, **own)
    killer = grades[0]
    if sandbox == "none":  # its parent is the worker: it dies, and the row says so
        assert killer.status == "worker died" and "KilledWorker" in killer.message
        # The honest script is graded as without the killer (after it, on a new worker).
        honest = grades[1]
        assert honest.status == "ok" and honest.report["sim_time_s"] > 1.5
        stdout = (tmp_path / "out" / "runs" / "b_honest.stdout.txt").read_text()
        assert "honest at 1.60" in stdout
    else:  # its parent is bubblewrap's init, which the kernel does not let it kill: it goes on
        assert killer.status == "exception" and killer.message.startswith(
            "RuntimeError: still here after killing my parent (at a_killer_bwrap.py:7 in <module>)"
        ), killer.message
    assert processes_with(tag) == []
    rows = len(grades)
    assert rows == (2 if sandbox == "none" else 1)
    assert len(list(csv.DictReader(open(tmp_path / "out" / "grades.csv")))) == rows
    assert (
        sorted(p.suffix for p in (tmp_path / "out" / "runs").iterdir())
        == [".json"] * rows + [".txt"] * 2 * rows
    )
    assert killer.isolation["sandbox"] == sandbox and not glob.glob(
        f"{tempfile.gettempdir()}/omtp-grade-{killer_name}-*"
    )


def test_ros_run_sandbox_runs_one_script_isolated(tmp_path, capsys, empty_cell):
    tag = uuid.uuid4().hex[:8]
    script = tmp_path / "writer.py"
    script.write_text(f"print('writing')\nopen('/var/tmp/escape_{tag}.txt', 'w').write('x')\n")
    result = tmp_path / "result.json"
    argv = ["ros-run", str(script), "--scenario", empty_cell, "--sandbox", "auto", "--json", str(result)]
    assert main(argv) == 1
    out = capsys.readouterr().out
    assert "writing" in out and "verdict: exception: PermissionError" in out
    assert f"refused by the sandbox: write to /var/tmp/escape_{tag}.txt" in out
    data = json.loads(result.read_text())
    assert data["status"] == "exception" and data["isolation"]["limits"] == asdict(Limits())
    assert not Path(f"/var/tmp/escape_{tag}.txt").exists()
    assert main(argv + ["--meshcat"]) == 2
    assert "--sandbox has no network" in capsys.readouterr().err


def test_a_folder_too_big_to_copy_per_run_is_refused(tmp_path):
    folder = tmp_path / "home"
    folder.mkdir()
    (folder / "student.py").write_text("print('hi')\n")
    for i in range(2001):
        (folder / f"photo_{i}.jpg").write_bytes(b"")
    with pytest.raises(ConfigError, match="holds over 2000 files or 200 MB"):
        grade_folder(folder, SCENARIO, workers=1)


#: Past the Python guard: a write by another program, a write and a connection through ctypes.
BYPASS = """
import ctypes, os, socket, subprocess
subprocess.run("echo x > /var/tmp/escape_{tag}.txt", shell=True)
libc = ctypes.CDLL(None, use_errno=True)
fd = libc.open(b"/var/tmp/escape2_{tag}.txt", os.O_WRONLY | os.O_CREAT, 0o644)
print("ctypes open:", fd, os.strerror(ctypes.get_errno()), flush=True)
s = socket.socket()
address = (ctypes.c_ubyte * 16)(2, 0, {port_hi}, {port_lo}, 127, 0, 0, 1)
print("ctypes connect:", libc.connect(s.fileno(), address, 16), os.strerror(ctypes.get_errno()))
"""


@pytest.mark.skipif(not bwrap_works(), reason="bubblewrap does not work here")
def test_bubblewrap_refuses_what_gets_past_the_guard(tmp_path, client, empty_cell):
    folder = tmp_path / "class"
    folder.mkdir()
    tag = uuid.uuid4().hex[:8]
    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(0.1)
    port = listener.getsockname()[1]
    (folder / "bypass.py").write_text(BYPASS.format(tag=tag, port_hi=port >> 8, port_lo=port & 255))
    (grade,) = grade_folder(folder, empty_cell, out=tmp_path / "out", sandbox="bwrap", client=client)
    assert grade.status == "ok"
    assert f"write to /var/tmp/escape_{tag}.txt (read-only)" in grade.refused
    out = (tmp_path / "out" / "runs" / "bypass.stdout.txt").read_text()
    assert "ctypes open: -1 Read-only file system" in out
    assert "ctypes connect: -1 " in out  # its own network: a loopback with nothing on it
    assert (
        not Path(f"/var/tmp/escape_{tag}.txt").exists() and not Path(f"/var/tmp/escape2_{tag}.txt").exists()
    )
    with pytest.raises(TimeoutError):
        listener.accept()
    listener.close()


def test_auto_falls_back_to_the_limits_with_one_warning_where_bubblewrap_fails(monkeypatch, caplog):
    from omtp_drake.grading import isolation

    monkeypatch.setattr(isolation, "BWRAP", str(Path(__file__).parent / "no_bwrap_here"))
    isolation.bwrap_works.cache_clear()
    isolation.resolve_sandbox.cache_clear()
    try:
        assert [isolation.resolve_sandbox("auto") for _ in range(3)] == ["none"] * 3
        warning = (
            f"no working bubblewrap ({isolation.BWRAP}): scripts run with the limits and the Python guard"
        )
        assert [r.message.startswith(warning) for r in caplog.records].count(True) == 1
        with pytest.raises(ConfigError, match="--sandbox bwrap: .*no_bwrap_here is missing or cannot create"):
            isolation.resolve_sandbox("bwrap")
        with pytest.raises(ConfigError, match="--sandbox 'docker' is unknown; valid: auto, bwrap, none"):
            isolation.resolve_sandbox("docker")
    finally:
        isolation.bwrap_works.cache_clear()
        isolation.resolve_sandbox.cache_clear()


def _error(e: BaseException) -> dict:
    from omtp_drake.errors import exception_kind

    return exception_kind(e)


@pytest.mark.parametrize(
    "error, exit_code, timed_out, verdict",
    [
        (MemoryError(), 0, False, "memory limit"),
        (OSError(12, "Cannot allocate memory"), 0, False, "memory limit"),
        (BlockingIOError(11, "Resource temporarily unavailable"), 0, False, "process limit"),
        (KeyError("x"), 0, False, "exception"),
        # The words do not decide: a KeyError that talks of memory and errno 11 is an exception.
        (KeyError("MemoryError [Errno 11] Resource temporarily unavailable"), 0, False, "exception"),
        (None, 3, False, "exited early"),
        (None, 0, True, "simulated timeout"),
        (None, 0, False, "ok"),
    ],
)  # fmt: skip
def test_a_reports_verdict_is_named_for_what_happened(error, exit_code, timed_out, verdict):
    from omtp_drake.grading.isolation import Outcome
    from omtp_drake.grading.verdicts import classify

    report = {
        "exception": f"{type(error).__name__}: {error}" if error is not None else None,
        "error": _error(error) if error is not None else None,
        "exit_code": exit_code,
        # The shutdown's words say timeout either way: only timed_out counts.
        "shutdown": "--timeout of 30 s simulated time reached",
        "timed_out": timed_out,
        "collisions": [],
        "callback_errors": [],
    }
    assert classify(Outcome(0, None, 1.0), report, "", LIMITS, 25.0)[0] == verdict


def test_without_a_report_the_guards_record_of_the_uncaught_exception_decides():
    from omtp_drake.grading.isolation import Outcome
    from omtp_drake.grading.verdicts import classify

    died = Outcome(1, None, 1.0, uncaught=_error(MemoryError()))
    assert classify(died, None, "", LIMITS, 25.0)[0] == "memory limit"
    # stderr's words are only shown: a tail that says MemoryError decides nothing.
    exited = Outcome(1, None, 1.0)
    assert classify(exited, None, "MemoryError", LIMITS, 25.0) == (
        "exited early",
        "exited early with code 1 (no report): MemoryError",
    )


def test_a_checkout_or_venv_under_tmp_stays_readable_in_bubblewrap(tmp_path, monkeypatch):
    """bubblewrap hides /tmp; a fresh clone or a virtual environment there (as CI's may be)
    is shown again read-only, once, under its outermost folder."""
    import sys

    from omtp_drake.grading.isolation import sandbox_prefix

    venv = tmp_path / "clone" / ".venv"
    (venv / "bin").mkdir(parents=True)
    monkeypatch.setattr(sys, "prefix", str(venv))
    monkeypatch.setattr(sys, "path", [str(tmp_path / "clone"), *sys.path])
    command = sandbox_prefix(tmp_path / "work", tmp_path / "work")
    binds = [command[i + 1] for i, a in enumerate(command) if a == "--ro-bind"]
    assert str((tmp_path / "clone").resolve()) in binds
    assert str(venv.resolve()) not in binds  # inside the clone: shown with it
    assert command.index("--tmpfs") < command.index("--ro-bind", command.index("--tmpfs"))


def test_the_guard_records_its_refusals_an_uncaught_exception_and_the_processes_left(tmp_path):
    """The grader reads what the guard saw as records, not from the run's messages. Inside
    bubblewrap the run's leftovers die with it, so the run counts them itself."""
    import subprocess
    import sys

    from omtp_drake.grading.guard import ENV, read_records

    records = tmp_path / "records.jsonl"
    script = tmp_path / "x.py"
    script.write_text(
        "import subprocess\n"
        "quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}\n"
        "kids = [subprocess.Popen(['sleep', '29.5071'], **quiet) for _ in range(2)]\n"
        "open('kids', 'w').write(' '.join(str(k.pid) for k in kids))\n"
        "try:\n    open('/var/tmp/nope_29.5071', 'w')\nexcept PermissionError:\n    pass\n"
        "raise MemoryError\n"
    )
    settings = {"limits": asdict(Limits()), "writable": [str(tmp_path)], "script": str(script),
                "parent": 0, "in_namespace": False, "records": str(records)}  # fmt: skip
    code = "from omtp_drake.grading.guard import install_from_env; install_from_env()\n"
    code += f"exec(compile(open({str(script)!r}).read(), {str(script)!r}, 'exec'))\n"
    env = {**os.environ, ENV: json.dumps(settings)}
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, start_new_session=True, capture_output=True, cwd=tmp_path
    )
    try:
        assert done.returncode == 1
        found = read_records(records)
        what = "write to /var/tmp/nope_29.5071 (outside the script's folder)"
        assert found[0] == {"refused": "open", "what": what}
        assert found[1]["uncaught"]["type"] == "MemoryError"
        assert found[2] == {"left_running": 2}
        assert not Path("/var/tmp/nope_29.5071").exists()
    finally:
        for pid in (tmp_path / "kids").read_text().split():
            with contextlib.suppress(OSError):
                os.kill(int(pid), signal.SIGKILL)


def test_the_watchers_scan_reads_new_processes_and_the_runs_own_again():
    """guard.ProcessScan, the run watcher's look every 50 ms: a process born after a look is
    in the next one, with its parent; the run's own are read again at each look (one that died,
    a zombie until reaped, is no longer there); another's first reading is kept."""
    import subprocess
    import time

    from omtp_drake.grading.guard import ProcessScan, descendants, process_table

    me = os.getpid()
    scan = ProcessScan()
    first = scan.table([me])
    assert first[me] == process_table()[me] and 1 in first
    scan.remember_others(first, [me])
    child = subprocess.Popen(["sleep", "30"])
    try:
        second = scan.table([me])
        assert second[child.pid][0] == me and child.pid in descendants([me], second)
        assert second[1] == first[1]
        scan.remember_others(second, [me, child.pid])
        child.kill()  # not reaped: a zombie, which process_table leaves out
        deadline = time.monotonic() + 10.0
        while child.pid in scan.table([me, child.pid]) and time.monotonic() < deadline:
            time.sleep(0.01)
        assert child.pid not in scan.table([me, child.pid])
    finally:
        child.kill()
        child.wait()
