"""The slides' set-up steps: `rosservice call ...` in a terminal, then the script
(``ros-run --call SERVICE --settle S``)."""

import pytest

from omtp_drake.errors import ConfigError
from omtp_drake.grading.cli import main


def test_assignment3_after_the_slides_call_finds_the_part(course_run):
    report, data = course_run(
        "a3_find_part.py",
        scenario="lecture6_assignment3",
        out_arg=True,
        calls=["/spawn_object_at_robot2"],
        settle=1.5,
    )
    assert report.ok, report.summary()
    assert data["start"] == pytest.approx(1.5)
    assert data["world"] == pytest.approx([-8.3, -1.23, 0.1], abs=0.01)
    # The scenario's object_1 is the slides' part: the call finds it in the world.
    assert len(report.empty_spawn_calls) == 1


def test_the_call_spawns_one_period_later_and_the_part_settles(course_run, tmp_path):
    scenario = tmp_path / "robot2.yaml"
    scenario.write_text(
        "base: omtp_factory\npart_pool: 2\nspawner: {xyz: [-8.3, -1.23, 0.55], period: 1.0, "
        "start_service: /spawn_object_at_robot2, stop_node: true}\n"
    )
    report, data = course_run(
        "a3_find_part.py", scenario=str(scenario), out_arg=True, calls=["/spawn_object_at_robot2"], settle=1.5
    )
    assert report.ok, report.summary()
    assert report.ledger["spawned"] == 1 and report.empty_spawn_calls == []
    assert data["world"] == pytest.approx([-8.3, -1.23, 0.1], abs=0.01)


def test_a_call_with_yaml_arguments_drives_the_belt(course_run):
    report, data = course_run(
        "belt_part_position.py",
        scenario="lecture6_assignment1",
        out_arg=True,
        calls=["/omtp/conveyor/control {state: {power: 100}}"],
        settle=1.0,
    )
    assert report.ok, report.summary()
    # 0.2 m/s at full power for 1 s, toward world -y (it starts at y = 1.8); the script's
    # get_model_state call takes the 5 ms service latency (ros_latency.service).
    assert data["t"] == pytest.approx(1.0 + 0.005) and data["y"] == pytest.approx(1.6, abs=0.02)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("/gripper2/control {enabled: true}", "has no field 'enabled'; fields: enable"),
        ("/spawn_object_once", "no service /spawn_object_once in this cell; its services: "),
    ],
)
def test_a_bad_call_is_one_clear_error_before_the_script(course_run, call, message):
    with pytest.raises(ConfigError, match=message):
        course_run("belt_part_position.py", scenario="lecture6_assignment3", out_arg=True, calls=[call])


def test_the_cli_takes_calls_and_settle(tmp_path, capsys):
    script = tmp_path / "hello.py"
    script.write_text("import rospy\nrospy.init_node('hello')\nrospy.loginfo('t = %.2f', rospy.get_time())\n")
    argv = ["ros-run", str(script), "--scenario", "lecture6_assignment4", "--call", "/spawn_object_at_robot2"]
    code = main([*argv, "--call", "/gripper2/control true", "--settle", "1.5", "-q"])
    out = capsys.readouterr().out
    assert code == 0 and "1.5 s simulated" in out and "spawned 1" in out
