"""The command line: outputs and clean errors (exit code 2, one line, no traceback)."""

import json
import logging
import subprocess
import sys
import warnings

import numpy as np
import pytest

from omtp_drake.cli import main


def run(*args):
    return subprocess.run([sys.executable, "-m", "omtp_drake.cli", *args],
                          capture_output=True, text=True, timeout=300)


def run_here(args, capsys, caplog):
    """``omtp-drake ARGS`` in this process (a fresh interpreter costs ~1.5 CPU s): its exit
    code and what a terminal would show on stderr: the error text, and any Python warning
    or log record at WARNING or above (a process would print those on stderr too, so they
    count against "one line")."""
    capsys.readouterr()
    caplog.clear()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            code = main(list(args))
        except SystemExit as e:  # argparse's own errors
            code = e.code
    err = capsys.readouterr().err
    err += "".join(f"{w.category.__name__}: {w.message}\n" for w in caught)
    err += "".join(f"{r.levelname} {r.name}: {r.getMessage()}\n"
                   for r in caplog.records if r.levelno >= logging.WARNING)
    return code, err


def test_scenarios_lists_names(capsys):
    assert main(["scenarios"]) == 0
    assert "omtp_factory" in capsys.readouterr().out


def test_tf_echo_json(capsys):
    assert main(["tf-echo", "omtp_factory", "robot1_base_link", "bin_1_base_link", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(out["translation"], [-8.5, -4.0, -0.95], atol=1e-3)
    np.testing.assert_allclose(out["rotation_xyzw"], [0, 0, 0, 1], atol=1e-9)


def test_tf_echo_at_named_pose(capsys):
    assert main(["tf-echo", "omtp_factory", "world", "vacuum_gripper2_suction_cup",
                 "--pose", "robot2=R2Place"]) == 0
    out = capsys.readouterr().out
    assert "- Translation: [-8.034, -2.095, 1.250]" in out  # reference: (-8.035, -2.095, 1.250) +/- 1 mm
    assert "in RPY (degree)" in out


#: One case per command family runs as its own process (what a user's shell sees); the rest
#: run in this process, their stderr and exit code read the same way (``run_here``).
IN_A_PROCESS = {"unknown scenario 'omtp_fctory'; valid: ", "replay '",
                "--seeds '-1:3' is an empty range; valid: START", "--seed must be an integer >= 0, got -1"}


@pytest.mark.parametrize("args, message", [
    (["tf-echo", "omtp_fctory", "world", "robot1_tool0"], "unknown scenario 'omtp_fctory'; valid: "),
    (
        ["tf-echo", "omtp_factory", "world", "robot1_tol0"],
        "unknown frame 'robot1_tol0'; closest: robot1_tool0",
    ),
    (["tf-echo", "omtp_factory", "world", "robot1_tool0", "--pose", "robot3=R1Up"], "unknown robot 'robot3'"),
    (
        ["tf-echo", "omtp_factory", "world", "robot1_tool0", "--pose", "robot1=R1Upp"],
        "unknown named pose of robot1 'R1Upp'",
    ),
    (["tf-echo", "omtp_factory", "world", "robot1_tool0", "--pose", "robot1"], "--pose takes ROBOT=POSE"),
    (["screenshot", "no_such_replay.html"], "replay '"),
    (["screenshot", "no_such_replay.html", "--size", "1280"], "--size takes WIDTHxHEIGHT"),
    # Ranges and values name the option the user wrote, in one line (no usage text).
    (["batch", "lecture6_assignment4", "--seeds", "-1:3"], "--seeds '-1:3' is an empty range; valid: START"),
    (["run", "lecture6_assignment4", "--seed", "-1"], "--seed must be an integer >= 0, got -1"),
    (["run", "lecture6_assignment4", "--parts", "x"], "argument --parts: invalid int value: 'x'"),
    (["run", "lecture6_assignment4", "--parts", "0"], "--parts must be >= 1, got 0"),
    (["run", "lecture6_assignment4", "--duration", "-5"], "--duration must be a finite time > 0 s, got -5.0"),
    (["tf-echo", "omtp_factory", "world", "robot1_tool0", "--time", "-1"], "--time -1.0 is invalid"),
])
def test_errors_are_one_line_without_traceback(args, message, capsys, caplog):
    if message in IN_A_PROCESS:
        result = run(*args)
        code, stderr = result.returncode, result.stderr
    else:
        code, stderr = run_here(args, capsys, caplog)  # a traceback would fail the test here
    assert code == 2
    assert message in stderr
    if "scenario" in message:
        assert "omtp_factory" in stderr
    assert "Traceback" not in stderr
    assert stderr.count("\n") == 1


def test_run_with_meshcat_and_no_terminal_prints_the_url_and_ends_cleanly():
    """Issue 11: `run --meshcat` (and --serve) from Jupyter's `!` or the background:
    the URL first, no EOFError, a note instead of serving."""
    result = subprocess.run(
        [sys.executable, "-m", "omtp_drake.cli", "run", "lecture6_assignment4", "--parts", "1",
         "--meshcat", "--serve", "-q"],
        capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("Meshcat: http://localhost:")
    assert "SUCCESS" in result.stdout and "no terminal attached" in result.stdout
    assert "Traceback" not in result.stderr and "EOFError" not in result.stderr


def test_progress_bar_shows_simulated_time_when_asked_and_stays_out_of_logs(capsys):
    assert main(["run", "lecture6_assignment4", "--parts", "1", "--duration", "1", "--progress"]) == 1
    err = capsys.readouterr().err
    assert "1.0/1 s simulated" in err and "0/1 in bin_1" in err
    # stderr is not a terminal here (a log): no bar, no carriage returns.
    assert main(["run", "lecture6_assignment4", "--parts", "1", "--duration", "1"]) == 1
    err = capsys.readouterr().err
    assert "s simulated" not in err and "\r" not in err


def test_tf_echo_reports_the_state_at_the_time_asked(capsys):
    """Issue 12: the part in free fall at T = 0.1 s is where the plant has it at T (it was
    one plant step later, 2 mm lower)."""
    from omtp_drake.sim.runtime import FactoryRuntime

    assert main(["tf-echo", "lecture6_assignment3", "world", "object_1", "--time", "0.1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    rt = FactoryRuntime("lecture6_assignment3")
    rt.advance_to(0.1)
    assert out["time"] == pytest.approx(0.1)
    np.testing.assert_allclose(out["translation"], rt.part_pose("object_1").translation(), atol=1e-9)
    assert main(["tf-echo", "lecture6_assignment3", "world", "logical_camera_2_object_1_frame",
                 "--time", "0.1", "--json"]) == 0
    seen = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(seen["translation"], rt.part_pose("object_1").translation(), atol=1e-9)


@pytest.mark.parametrize("text, message", [
    ("", "the file is empty; a scenario needs keys"),
    ("# only a comment\n", "the file is empty; a scenario needs keys"),
    (
        "base: omtp_factory\nparts:\n  - {name: p, xyz: [0, 0, 1]}\n  - {name: p, xyz: [1, 0, 1]}\n",
        "parts: name 'p' is given twice; names in a list must be unique",
    ),
    (
        "base: omtp_factory\ncameras:\n  - {name: logical_camera_1, near: 0.3}\n"
        "  - {name: logical_camera_1}\n",
        "cameras: name 'logical_camera_1' is given twice",
    ),
    ("base: omtp_factory\nseed: -3\n", "seed must be an integer >= 0, got -3"),
])
def test_scenario_files_that_are_refused_in_one_line(tmp_path, text, message, capsys, caplog):
    path = tmp_path / "mine.yaml"
    path.write_text(text)
    args = ("tf-echo", str(path), "world", "robot1_tool0")
    if text == "":  # one as its own process; the rest in this one (see IN_A_PROCESS)
        result = run(*args)
        code, stderr = result.returncode, result.stderr
    else:
        code, stderr = run_here(args, capsys, caplog)
    assert code == 2
    assert message in stderr
    assert stderr.count("\n") == 1


def test_a_scripts_own_arguments_reach_it_as_given(tmp_path):
    """Only omtp-drake's options are read for values like -1 (--seeds -1:3 is the option's
    value); what follows the script is the script's, untouched."""
    script = tmp_path / "args.py"
    out = tmp_path / "argv.json"
    script.write_text(f"import json, sys\njson.dump(sys.argv[1:], open({str(out)!r}, 'w'))\n")
    result = run("ros-run", "--scenario", "omtp_factory", str(script), "--", "--offset", "-0.5", "-3")
    assert result.returncode == 0, result.stderr
    assert json.loads(out.read_text()) == ["--offset", "-0.5", "-3"]
