"""Gazebo's own ROS API: gazebo_msgs, /gazebo/model_states and link_states, the model
and link state services, spawning the course's part, delete, pause (gazebo_ros'
gazebo_ros_api_plugin.cpp)."""

import pytest

A3 = "lecture6_assignment3"


def test_model_state_services_find_the_part_where_it_rests(course_run):
    report, data = course_run("model_state_services.py", scenario=A3, out_arg=True, args=["none"])
    assert report.ok, report.summary()
    x, y, z, w, ok = data["rest"]
    # The 0.2 m part dropped at (-8.3, -1.23, 0.55) rests on the floor, unturned.
    assert ok and (x, y, z) == pytest.approx((-8.3, -1.23, 0.1), abs=5e-3) and w == pytest.approx(1, abs=1e-3)
    # Relative to robot 2 (base at (-7.8, -1.5), turned 1.57 about z): Gazebo's model - frame.
    rx, ry, _ = data["in_robot2"]
    assert (rx, ry) == pytest.approx((0.27, 0.5), abs=0.01)
    assert data["missing"] == [False, "GetModelState: model does not exist"]


def test_set_model_state_moves_the_part_into_the_bin(course_run):
    report, data = course_run("model_state_services.py", scenario=A3, out_arg=True, args=["move"])
    assert report.ok, report.summary()
    assert data["set"] == [True, "SetModelState: set model state done"]
    assert report.ledger["in_bin"]["bin_1"] == 1 and report.ledger["on_floor"] == 0


def test_delete_model_takes_the_part_out_of_the_world(course_run):
    report, data = course_run("model_state_services.py", scenario=A3, out_arg=True, args=["delete"])
    assert report.ok, report.summary()
    assert data["delete"] == [True, "DeleteModel: successfully deleted model"]
    assert data["again"] == [False, False]  # no such model any more
    assert report.ledger["disposed"] == 1 and report.ledger["on_floor"] == 0
    assert "object_1" not in report.ledger["parts"]


def test_spawn_urdf_model_spawns_the_course_part_under_its_name(course_run):
    report, data = course_run("spawn_course_part.py", scenario="lecture6_assignment4", out_arg=True)
    assert report.ok, report.summary()
    assert data["first"] == [True, "SpawnModel: Successfully spawned entity"]
    assert data["again"] == [False, "SpawnModel: Failure - model already exists."]
    # Dropped at (1.2, 1.8, 1.1) onto the stopped belt.
    assert report.ledger["spawned"] == 1 and report.ledger["on_belt"] == 1
    assert data["models"][-1] == "object_7"


def test_spawn_sdf_model_of_another_model_is_one_clear_error(course_run):
    report, _ = course_run("spawn_course_part.py", scenario="lecture6_assignment4", out_arg=True, args=["x"])
    assert report.exception.startswith(
        "NotSupportedError: /gazebo/spawn_sdf_model: this cell spawns the course's"
    )
    assert "package://omtp_gazebo/meshes/conveyor_objects/box.stl" in report.exception
    assert "shapes sphere" in report.exception


def test_pause_physics_stops_the_clock_and_the_fall(course_run):
    report, data = course_run("pause_physics.py", scenario=A3, out_arg=True)
    assert report.ok, report.summary()
    t0, z0 = data["paused"]
    assert data["later"] == [t0, z0]  # wall time passed, nothing moved
    assert 0.1 < z0 < 0.55  # it was falling
    t1, z1 = data["running"]
    assert t1 == pytest.approx(t0 + 1.0, abs=0.06) and z1 == pytest.approx(0.1, abs=5e-3)


def test_a_sleep_while_paused_ends_the_run_as_a_hang_would(course_run):
    report, data = course_run("pause_physics.py", scenario=A3, out_arg=True, args=["sleep"])
    assert report.exception is None and "physics is paused" in report.shutdown
    assert report.sim_time_s == pytest.approx(data["paused"][0])


def test_model_and_link_states_come_at_every_physics_update(course_run):
    report, data = course_run("model_link_states.py", scenario=A3, out_arg=True)
    assert report.ok, report.summary()
    # One message per plant step (0.01 s) during the 1 s sleep.
    assert data["n"] == {"model": 100, "link": 100}
    assert {"robot1", "robot2", "bin_1_", "conveyor_belt", "object_1"} <= set(data["last"]["models"])
    assert "robot2::vacuum_gripper2_suction_cup" in data["last"]["links"]
    assert data["part"] == pytest.approx([-8.3, -1.23, 0.1], abs=5e-3)
    assert data["cup"][2] > 0.5


def test_importing_gazebo_msgs_unused_runs(course_run):
    script = """
        import rospy
        from gazebo_msgs.srv import SpawnModel
        from gazebo_msgs.msg import ModelState, ModelStates, LinkState, LinkStates
        rospy.init_node('imports')
        rospy.sleep(0.1)
    """
    report, _ = course_run(script, scenario=A3)
    assert report.ok, report.summary()


def test_reset_world_puts_the_part_back_where_it_was_dropped(course_run):
    script = """
        import json, sys
        import rospy
        from std_srvs.srv import Empty
        from gazebo_msgs.srv import GetModelState
        rospy.init_node('reset')
        rospy.sleep(1.5)
        rospy.ServiceProxy('/gazebo/reset_world', Empty)()
        z = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)('object_1', 'world').pose.position.z
        with open(sys.argv[1], 'w') as f:
            json.dump({'z': z}, f)
        rospy.ServiceProxy('/gazebo/reset_simulation', Empty)()
    """
    report, data = course_run(script, scenario=A3, out_arg=True)
    assert data["z"] == pytest.approx(0.55, abs=1e-6)
    assert report.exception.startswith("NotSupportedError: /gazebo/reset_simulation")


def test_a_model_state_published_to_gazebo_moves_the_part(course_run):
    report, _ = course_run("teleport_by_topic.py", scenario=A3)
    assert report.ok, report.summary()
    assert report.ledger["in_bin"]["bin_1"] == 1 and report.ledger["on_floor"] == 0
