"""The course's spawner as its launch files wire it (conveyor_spawner.cpp, the launch
files' remaps, omtp_utilities' spawn_object_once.py): a periodic timer started by the
remapped start_spawn, stopped by /stop_spawn; a call that spawns nothing answers
normally, logs one warning and is counted in the report."""

import pytest

#: lecture6_assignment3.launch's spawner without a part at the start; with or without
#: the spawn_object_once node.
ROBOT2_SPAWNER = """
base: omtp_factory
part_pool: 6
spawner:
  xyz: [-8.3, -1.23, 0.55]
  period: 1.0
  start_service: /spawn_object_at_robot2
  stop_node: {stop_node}
"""


@pytest.fixture
def robot2_spawner(tmp_path):
    def scenario(stop_node: bool) -> str:
        path = tmp_path / f"robot2_spawner_{stop_node}.yaml"
        path.write_text(ROBOT2_SPAWNER.format(stop_node=str(stop_node).lower()))
        return str(path)

    return scenario


def test_a_node_stopping_the_spawner_on_model_states_leaves_one_part(course_run, robot2_spawner):
    report, data = course_run("stop_spawn_on_object.py", scenario=robot2_spawner(False), out_arg=True)
    assert report.ok, report.summary()
    assert report.ledger["spawned"] == 1
    assert [m for m in data["models"] if "object" in m] == ["object_1"]


def test_without_a_stop_the_spawner_spawns_every_period(course_run, robot2_spawner):
    report, _ = course_run("spawn_and_wait.py", scenario=robot2_spawner(False))
    # Started at t = 0: parts at t = 1, 2 and 3 s; the second call, while it runs, changes nothing.
    assert report.ok and report.ledger["spawned"] == 3
    assert len(report.empty_spawn_calls) == 1 and "runs already" in report.empty_spawn_calls[0]


def test_a_spawn_call_from_a_callback_with_a_part_in_the_world_spawns_nothing(course_run):
    report, data = course_run("spawn_in_callback.py", scenario="lecture6_assignment3", out_arg=True)
    assert report.ok and report.callback_errors == [], report.summary()
    assert len(data["calls"]) == 1 and data["spawned"] == []
    assert report.ledger["spawned"] == 1  # the scenario's object_1 only
    (warning,) = report.empty_spawn_calls
    assert "/spawn_object_at_robot2: nothing spawned: object_1 is in the world" in warning


def test_spawned_part_is_latched_with_the_spawn_count_and_time(course_run, robot2_spawner):
    report, data = course_run("spawn_in_callback.py", scenario=robot2_spawner(True), out_arg=True)
    assert report.ok, report.summary()
    (called,) = data["calls"]
    ((seq, stamp, frame_id),) = data["spawned"]
    assert (seq, frame_id) == (1, "box") and stamp == pytest.approx(called + 1.0, abs=0.011)
    assert report.ledger["spawned"] == 1 and report.empty_spawn_calls == []


def test_ros_runs_own_spawn_service_refusing_a_second_part_warns(course_run):
    report, _ = course_run("spawn_and_wait.py", scenario="lecture6_assignment4")
    assert report.ok, report.summary()
    assert report.ledger["spawned"] == 1
    (warning,) = report.empty_spawn_calls
    assert "one part at a time: object_1 is still in the world" in warning


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"start_service": "spawn_object_at_robot2", "period": 1.0}, "needs a global name"),
        ({"start_service": "/spawn_object_at_robot2", "period": 0.0}, "got period 0.0"),
        ({"stop_node": True}, "stop_node needs spawner.start_service"),
    ],
)
def test_the_launch_wiring_in_a_scenario_is_checked(fields, message):
    from omtp_drake.errors import ConfigError
    from omtp_drake.scenario import SpawnerConfig

    with pytest.raises(ConfigError, match=message):
        SpawnerConfig(**fields).validate()


def test_lecture7_feeder_spawns_every_3_s_until_stopped(course_run):
    report, data = course_run("feeder_on_off.py", scenario="lecture7_conveyor", out_arg=True)
    assert report.ok, report.summary()
    # omtp_pick_demo.launch: /start_spawn not remapped, a part every 3 s, whatever is loose.
    assert data["remapped"] is False
    # The timer starts when the /start_spawn call arrives (5 ms service latency), so the
    # spawns come at the first physics steps (10 ms) after 3.005 s and 6.005 s.
    assert data["seen"] == [[1, 3.01, "box"], [2, 6.01, "box"]]
    assert report.ledger["spawned"] == 2


def test_lecture6_robot1_belt_spawner_is_behind_spawn_object_once(course_run):
    """lecture6_assignment1.launch's wiring (the course's robot-1 assignment 4 ran on it):
    conveyor_objects.yaml's box every 10 s behind /spawn_object_once, no stop node."""
    report, data = course_run(
        """\
        import json, sys
        import rospy
        from std_msgs.msg import Header
        from std_srvs.srv import Empty
        rospy.init_node('belt_feeder')
        spawned = []
        rospy.Subscriber('/spawned_part', Header, lambda m: spawned.append(round(m.stamp.to_sec(), 2)))
        rospy.ServiceProxy('/spawn_object_once', Empty)()
        while len(spawned) < 2 and rospy.get_time() < 25.0:  # (the second is due at 20 s)
            rospy.sleep(0.1)
        json.dump(spawned, open(sys.argv[1], 'w'))
        """,
        scenario="lecture6_assignment4_robot1",
        out_arg=True,
        settle_after=0,  # the spawns are the subject: not the 3 s the riding part takes not to rest
    )
    assert report.ok, report.summary()
    assert data == [10.01, 20.01]  # one period after the call (5 ms latency), at the next 10 ms step
    assert report.ledger["spawned"] == 2 and report.empty_spawn_calls == []
