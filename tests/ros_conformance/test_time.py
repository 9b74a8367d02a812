"""Simulated time passes while a script thinks, and suction attaches by the course plugin's
rule: the commonest course habit (press the cup onto the part, ``gripper(True)``, then move
away at once) picks the part as in the course's Gazebo cell, through ``go()``, through
``compute_cartesian_path`` and the ``execute_trajectory`` action, and through Melodic's
``plan()`` + ``execute``. Without the latency (``--latency 0``) the arm leaves before the
plugin's second check and the part stays on the floor."""

import json
from pathlib import Path

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm.latency import resolve_latency
from omtp_drake.scenario import load_scenario
from omtp_drake.scenario.latency import RosLatencyConfig

SCENARIO = "lecture6_assignment4"
#: The defaults (omtp_drake/scenario/latency.py says where each comes from).
DEFAULT = RosLatencyConfig()


def parts_in_bin_1(report) -> int:
    return report.ledger["in_bin"]["bin_1"]


@pytest.mark.parametrize(
    "script, moveit",
    [
        ("grip_then_go.py", "noetic"),
        ("grip_then_cartesian_action.py", "noetic"),
        ("grip_then_plan_melodic.py", "melodic"),
    ],
)
def test_gripper_on_then_move_at_once_puts_the_part_in_the_bin(course_run, script, moveit):
    report, _ = course_run(script, scenario=SCENARIO, moveit=moveit)
    assert report.exception is None and not report.collisions
    assert parts_in_bin_1(report) == 1
    assert report.ledger["on_floor"] == 0 and sum(report.ledger["held"].values()) == 0


@pytest.mark.parametrize("script, moveit", [("grip_then_plan_melodic.py", "melodic")])
def test_without_latency_the_arm_leaves_before_the_second_check(course_run, script, moveit):
    """A cell that stands still while the script plans: the arm is gone before the
    plugin's second check (0.1 s after the enable), the part stays on the floor.
    (grip_then_go.py with noetic's API: test_ros_run_latency_flag's ``--latency 0`` run.)"""
    report, _ = course_run(script, scenario=SCENARIO, moveit=moveit, latency=0)
    assert report.exception is None
    assert parts_in_bin_1(report) == 0 and report.ledger["on_floor"] == 1


def test_calls_take_the_scenarios_latency(course_run):
    report, took = course_run("call_times.py", scenario=SCENARIO, out_arg=True)
    assert report.exception is None, report.exception
    assert took["service"] == pytest.approx(DEFAULT.service, abs=1e-9)
    assert took["plan"] == pytest.approx(DEFAULT.plan, abs=1e-9)
    assert took["planning_time"] == pytest.approx(DEFAULT.plan, abs=1e-9)  # what plan() reports
    assert took["cartesian"] == pytest.approx(DEFAULT.cartesian, abs=1e-9)
    _, none = course_run("call_times.py", scenario=SCENARIO, out_arg=True, latency=0)
    assert none["service"] == none["plan"] == none["cartesian"] == 0.0
    # execute: the start's latency before the same motion (and the arm's settling after it).
    assert none["execute"] >= none["duration"]
    assert took["execute"] - none["execute"] == pytest.approx(DEFAULT.execute, abs=0.011)
    # go: planning, then the start.
    assert took["go"] - none["go"] == pytest.approx(DEFAULT.plan + DEFAULT.execute, abs=0.011)


def test_go_without_waiting_returns_at_once_and_moves_after_planning(course_run):
    """``go(wait=False)`` returns at once; move_group plans and starts the motion
    ``plan + execute`` (0.105 s) later, while the script goes on."""
    report, data = course_run("go_no_wait.py", scenario=SCENARIO, out_arg=True)
    assert report.exception is None, report.exception
    assert data["returned"] == 0.0
    # Sampled at 0.05, 0.10, 0.15... s: still at 0.05 and 0.10, moving from 0.15 (rad).
    assert max(data["moved"][:2]) < 1e-6
    assert 1e-3 < data["moved"][2] < data["moved"][3] < data["moved"][5]
    # With no latency it has moved by the first sample.
    _, data = course_run("go_no_wait.py", scenario=SCENARIO, out_arg=True, latency=0)
    assert data["moved"][0] > 5e-4


#: The service, plan and cartesian calls of call_times.py, without its motions (the latencies
#: a scenario or --latency sets are read from these three; the motions' are tested above).
PLANNING_CALLS = "planning_call_times.py"


def test_latency_is_set_in_the_scenario_and_on_the_command_line(course_run, tmp_path):
    scenario = tmp_path / "slow_planner.yaml"
    scenario.write_text(f"base: {SCENARIO}\nros_latency: {{plan: 0.5, cartesian: 0.25}}\n")
    report, took = course_run(PLANNING_CALLS, scenario=str(scenario), out_arg=True)
    assert report.exception is None, report.exception
    assert took["plan"] == pytest.approx(0.5, abs=1e-9) and took["cartesian"] == pytest.approx(0.25, abs=1e-9)
    assert took["service"] == pytest.approx(DEFAULT.service, abs=1e-9) and took["fraction"] == 1.0
    _, took = course_run(
        PLANNING_CALLS, scenario=str(scenario), out_arg=True, latency="plan=0.2,service=0.05"
    )
    assert took["plan"] == pytest.approx(0.2, abs=1e-9) and took["service"] == pytest.approx(0.05, abs=1e-9)
    assert took["cartesian"] == pytest.approx(0.25, abs=1e-9)
    # A factor scales the scenario's delays (the run takes what resolve_latency gives, as above).
    factor = resolve_latency(load_scenario(str(scenario)).ros_latency, "2")
    assert (factor.plan, factor.cartesian, factor.service) == pytest.approx((1.0, 0.5, 2 * DEFAULT.service))


@pytest.mark.parametrize(
    "spec, words",
    [
        ("fast", ["fast", "factor", "plan, execute, cartesian, service"]),
        ("warp=1", ["unknown delay 'warp'", "plan, execute, cartesian, service"]),
        ("plan=soon", ["plan='soon'", "seconds"]),
        ("plan=20", ["ros_latency.plan", "[0, 10] s", "20"]),
        ("-1", ["factor", ">= 0", "-1"]),
    ],
)
def test_a_bad_latency_is_refused_with_the_valid_choices(spec, words):
    with pytest.raises(ConfigError) as info:
        resolve_latency(DEFAULT, spec)
    for word in words:
        assert word in str(info.value)


def test_a_bad_latency_in_the_scenario_is_refused(course_run, tmp_path):
    scenario = tmp_path / "bad.yaml"
    scenario.write_text(f"base: {SCENARIO}\nros_latency: {{service: -0.1}}\n")
    with pytest.raises(ConfigError, match=r"ros_latency.service must be in \[0, 10\] s, got -0.1"):
        course_run(PLANNING_CALLS, scenario=str(scenario), out_arg=True)


def test_ros_run_latency_flag(tmp_path):
    """``omtp-drake ros-run SCRIPT --latency ...``: the command line reaches the run. The
    ``--latency 0`` run is also grip_then_go.py's (noetic) case of
    test_without_latency_the_arm_leaves_before_the_second_check: the part stays on the floor."""
    from omtp_drake.grading.cli import main

    script = Path(__file__).parent / "scripts" / "grip_then_go.py"
    out = tmp_path / "report.json"
    argv = ["ros-run", str(script), "--scenario", SCENARIO, "-q", "--json", str(out)]
    assert main([*argv, "--latency", "0"]) == 0
    report = json.loads(out.read_text())
    assert report["exception"] is None
    assert report["ledger"]["in_bin"]["bin_1"] == 0 and report["ledger"]["on_floor"] == 1
    # A spec reaches the run's calls (the part in the bin with the default latency:
    # test_gripper_on_then_move_at_once_puts_the_part_in_the_bin[grip_then_go.py-noetic]).
    took = tmp_path / "took.json"
    calls = Path(__file__).parent / "scripts" / PLANNING_CALLS
    assert main(["ros-run", str(calls), str(took), *argv[2:], "--latency", "plan=0.1,service=0.03"]) == 0
    assert json.loads(out.read_text())["exception"] is None
    calls_took = json.loads(took.read_text())
    assert calls_took["plan"] == pytest.approx(0.1, abs=1e-9)
    assert calls_took["service"] == pytest.approx(0.03, abs=1e-9)
    assert main([*argv, "--latency", "soon"]) == 2
