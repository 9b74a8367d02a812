"""A run's report is taken once the cell has settled: after the script or behaviour ends the
world runs on (simulated time) until every part rests, at most ``--settle-after`` seconds,
as Gazebo's world runs on after the course's script."""

import json
from pathlib import Path

import pytest

from omtp_drake.cli import main
from omtp_drake.errors import ConfigError
from omtp_drake.ros.flexbe import run_behavior

ROOT = Path(__file__).resolve().parents[2]
RELEASE = Path(__file__).parent / "scripts" / "flexbe_release"
EXAMPLE_STATES = ROOT / "examples" / "flexbe"


def _quick_feeder(tmp_path: Path) -> str:
    """lecture7_flexbe with its feeder's part 1 s after /start_spawn (not 3 s) and 0.4 m further
    down the belt: the behaviour (its 'feed one part' waits 1.5 s) picks it about 3 s sooner;
    what happens after the pick, the subject here, is the same."""
    path = tmp_path / "quick_feeder.yaml"
    path.write_text("base: lecture7_flexbe\nspawner: {xyz: [1.2, 2.2, 1.021], period: 1.0}\n")
    return str(path)


def test_a_behaviour_that_lets_go_and_finishes_leaves_the_part_on_the_floor(tmp_path):
    """Robot 1 picks the part the beam stops, turns to R1Place (no bin there) and switches
    suction off; the behaviour's next outcome is ``finished``. The part falls to the floor."""
    workspaces = [RELEASE, EXAMPLE_STATES]
    scenario = _quick_feeder(tmp_path)
    report = run_behavior("Pick And Release", workspaces, scenario=scenario, timeout=60)
    assert report.outcome == "finished" and report.ok, report.summary()
    assert report.trace[-1]["state"] == "/gripper off"
    assert report.ledger["parts"] == {"object_1": "on_floor"} and report.ledger["held"]["robot1"] == 0
    # It falls about 1 m and comes to rest within the 3 s; sleep.rest_time (0.5 s) of stillness
    # is the least the world runs on.
    assert report.at_rest and 0.5 <= report.settle_s < 3.0
    assert report.ledger["time"] == pytest.approx(report.sim_time_s + report.settle_s)
    assert "settled: the cell ran on" in report.summary()

    # --settle-after 0: the report at the outcome, as before: the gripper has not let go yet.
    out = tmp_path / "run.json"
    args = ["flexbe-run", "Pick And Release", "--workspace", str(RELEASE), "--workspace", str(EXAMPLE_STATES)]
    code = main(args + ["--scenario", scenario, "--settle-after", "0", "--json", str(out), "-q"])
    at_once = json.loads(out.read_text())
    assert code == 0 and at_once["settle_s"] == 0.0
    assert at_once["ledger"]["parts"] == {"object_1": "held:robot1"}
    assert at_once["sim_time_s"] == pytest.approx(report.sim_time_s)


def test_a_script_that_ends_while_its_part_falls_reports_where_it_lands(course_run):
    report, _ = course_run(
        """\
        import rospy
        from std_srvs.srv import Empty
        rospy.init_node("drop")
        rospy.ServiceProxy("/spawn_object_at_robot2", Empty)()  # the part falls from 0.55 m
        """,
        scenario="lecture6_assignment4",
    )
    assert report.ok, report.summary()
    assert report.sim_time_s == pytest.approx(0.005)  # the call's own time
    assert report.ledger["parts"] == {"object_1": "on_floor"} and report.at_rest


def test_a_part_that_never_rests_runs_the_whole_limit(course_run):
    report, _ = course_run(
        """\
        import rospy
        from omtp_gazebo.msg import ConveyorBeltState
        from omtp_gazebo.srv import ConveyorBeltControl
        rospy.init_node("belt")
        rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)(ConveyorBeltState(power=100))
        """,
        scenario="lecture6_assignment1",
        settle_after=0.4,
    )
    assert report.ok, report.summary()
    assert report.settle_s == pytest.approx(0.4) and not report.at_rest
    assert "the --settle-after limit; not every part at rest" in report.summary()
    assert list(report.ledger["parts"].values()) == ["on_belt"]


@pytest.mark.parametrize("value", [-1.0, float("nan"), float("inf")])
def test_a_bad_settle_after_is_one_clear_error(course_run, value):
    message = r"--settle-after must be finite simulated seconds >= 0 \(0: none\)"
    with pytest.raises(ConfigError, match=message):
        course_run("import rospy\n", scenario="lecture6_assignment3", settle_after=value)


def test_settle_after_reaches_an_isolated_run(tmp_path):
    """``ros-run --sandbox`` passes --settle-after on, 0 included (a 0 was dropped as unset)."""
    script = tmp_path / "drop.py"
    script.write_text(
        "import rospy\nfrom std_srvs.srv import Empty\nrospy.init_node('drop')\n"
        "rospy.ServiceProxy('/spawn_object_at_robot2', Empty)()\n"
    )
    result = tmp_path / "result.json"
    argv = ["ros-run", str(script), "--scenario", "lecture6_assignment4", "--sandbox", "auto", "-q"]
    assert main(argv + ["--settle-after", "0", "--json", str(result)]) == 0
    report = json.loads(result.read_text())["report"]
    assert report["settle_s"] == 0.0 and report["ledger"]["parts"]["object_1"].startswith("elsewhere")
    assert main(argv + ["--json", str(result)]) == 0
    report = json.loads(result.read_text())["report"]
    assert report["at_rest"] and report["ledger"]["parts"] == {"object_1": "on_floor"}


def test_a_world_without_parts_rests_at_once(tmp_path):
    """The tutorial's robot alone in Gazebo's empty world: no part to wait for, so the report
    is taken at the first tick after the end, not after the whole --settle-after."""
    from omtp_drake.ros.run.runner import run_script

    robot = ROOT / "tests" / "fixtures" / "tutorial_ws" / "src" / "slider_arm_description" / "urdf"
    script = tmp_path / "hello.py"
    script.write_text("import rospy\nrospy.init_node('hello')\nrospy.sleep(0.2)\n")
    report = run_script(script, robot=robot / "slider_arm.urdf.xacro", timeout=5)
    assert report.ok and report.at_rest and report.settle_s < 0.5, report.summary()
