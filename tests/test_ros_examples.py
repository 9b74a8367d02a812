"""The course-style ROS scripts of examples/ros, run unmodified by ros-run, to their outcomes
(from the ledger; shortened with a PARTS argument where they loop)."""

import json
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.cli import main
from omtp_drake.ros import run_script

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "ros"


def test_every_ros_example_is_tested():
    assert sorted(p.stem for p in EXAMPLES.glob("*.py")) == [
        "cartesian_descent", "lecture6_assignment3", "lecture6_assignment4", "lecture7_belt_pick"]


def test_assignment3_prints_the_part_in_the_suction_cup_frame(capsys):
    report = run_script(EXAMPLES / "lecture6_assignment3.py", scenario="lecture6_assignment3")
    assert report.ok and report.ledger["on_floor"] == 1
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("part in vacuum_gripper2"))
    p = np.array([float(v) for v in line.split("(")[1].rstrip(")").split(",")])
    # The reference: the part rests at (-8.3, -1.23, 0.1); the cup frame at R2Home is at
    # (-8.287, -1.609, 1.122), pointing straight down: the part is 1.022 m along its axis.
    assert p[2] == pytest.approx(1.022, abs=3e-3)
    assert np.linalg.norm(p) == pytest.approx(np.linalg.norm([-0.013, 0.379, 1.022]), abs=3e-3)


@pytest.fixture(scope="module")
def reports():
    """A script's report, run once per module (cartesian_descent's serves two tests)."""
    cache: dict = {}

    def report(script, args, scenario):
        key = (script, tuple(args), scenario)
        if key not in cache:
            cache[key] = run_script(EXAMPLES / f"{script}.py", args, scenario=scenario, timeout=60.0)
        return cache[key]

    return report


@pytest.mark.parametrize("script, args, scenario, bin_name, parts", [
    ("lecture6_assignment4", ["2"], "lecture6_assignment4", "bin_1", 2),
    ("cartesian_descent", [], "lecture6_assignment4", "bin_1", 1),
    ("lecture7_belt_pick", ["1"], "lecture7_conveyor_pick", "bin_2", 1),
])
def test_pick_scripts_put_the_parts_in_the_bin(reports, script, args, scenario, bin_name, parts):
    report = reports(script, args, scenario)
    assert report.exception is None and report.collisions == [] and report.callback_errors == []
    ledger = report.ledger
    assert ledger["in_bin"][bin_name] == parts and sum(ledger["held"].values()) == 0
    assert ledger["on_floor"] == 0 and ledger["elsewhere"] == 0


def test_ros_run_command_refuses_a_missing_script(tmp_path, capsys):
    assert main(["ros-run", str(tmp_path / "missing.py"), "--scenario", "lecture6_assignment3"]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_two_runs_of_an_example_give_the_same_report(reports, tmp_path):
    """Same script, scenario and seed: the same report, but for the wall time. The first run
    is the one test_pick_scripts_put_the_parts_in_the_bin checked (in this process); the
    second goes through the command line, whose --json file is that report."""
    out = tmp_path / "result.json"
    argv = ["ros-run", str(EXAMPLES / "cartesian_descent.py"), "--scenario", "lecture6_assignment4"]
    assert main([*argv, "--timeout", "60", "--json", str(out), "-q"]) == 0
    data = json.loads(out.read_text())
    assert set(data) >= {"ledger", "sim_time_s", "wall_time_s", "exception", "collisions"}
    first = json.loads(json.dumps(reports("cartesian_descent", [], "lecture6_assignment4").to_dict()))
    for run in (first, data):
        run.pop("wall_time_s")
    assert data == first and data["exception"] is None
    assert data["ledger"]["spawned"] == 1 and data["ledger"]["in_bin"]["bin_1"] == 1
