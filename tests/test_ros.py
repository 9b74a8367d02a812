"""The ROS layer (omtp_drake.ros): course-style scripts run by ros-run, in simulated time.

Each test writes a small ROS script, runs it with run_script and checks what it
saw (it writes JSON to the path it gets as its argument) and the run's report."""

import json
import sys
import textwrap

import numpy as np
import pytest

from omtp_drake.ros import run_script

A3 = "lecture6_assignment3"


def run(tmp_path, source, scenario=A3, name="script.py", **options):
    script = tmp_path / name
    script.write_text(textwrap.dedent(source))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=scenario, **options)
    data = json.loads(out.read_text()) if out.is_file() else None
    return report, data


def test_time_sleep_rate_and_camera_messages_in_time_order(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        from omtp_gazebo.msg import LogicalCameraImage
        rospy.init_node("timing")
        stamps = []
        on_image = lambda m: stamps.append(rospy.get_time())
        rospy.Subscriber("omtp/logical_camera_2", LogicalCameraImage, on_image)
        t0 = rospy.Time.now()
        rospy.sleep(1.0)
        t1 = rospy.get_time()
        rate = rospy.Rate(10)
        for _ in range(5):
            rate.sleep()
        out = {"t0": t0.to_sec(), "t1": t1, "t2": rospy.get_time(), "stamps": stamps}
        json.dump(out, open(sys.argv[1], "w"))
    """)
    assert report.ok and report.exception is None
    assert data["t0"] == 0.0 and data["t1"] == pytest.approx(1.0) and data["t2"] == pytest.approx(1.5)
    stamps = np.array(data["stamps"])
    assert 13 <= len(stamps) <= 16  # a 10 Hz camera over 1.5 s
    assert np.all(np.diff(stamps) > 0)


def test_a_callback_that_blocks_holds_its_queue_and_never_reenters(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        from omtp_gazebo.msg import LogicalCameraImage
        rospy.init_node("slow_callback")
        calls, inside = [], [False]
        def slow(msg):
            assert not inside[0], "re-entered"
            inside[0] = True
            start = rospy.get_time()
            rospy.sleep(0.35)  # holds this subscriber's queue
            calls.append((start, rospy.get_time()))
            inside[0] = False
        rospy.Subscriber("/omtp/logical_camera_2", LogicalCameraImage, slow, queue_size=1)
        rospy.sleep(2.0)
        json.dump(calls, open(sys.argv[1], "w"))
    """)
    assert report.callback_errors == [] and report.ok
    calls = np.array(data)
    assert len(calls) >= 4
    assert np.all(calls[1:, 0] >= calls[:-1, 1] - 1e-9)  # one at a time, in order
    assert np.all(np.diff(calls[:, 0]) < 0.5)  # the newest queued message comes right after


def test_spin_ends_at_the_timeout_and_signal_shutdown_ends_it_earlier(tmp_path):
    report, _ = run(tmp_path, """
        import rospy
        rospy.init_node("spinner")
        rospy.spin()
    """, timeout=1.0)
    assert report.exception is None and "timeout" in report.shutdown
    assert report.sim_time_s == pytest.approx(1.0)
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        rospy.init_node("spinner")
        rospy.on_shutdown(lambda: json.dump({"t": rospy.get_time()}, open(sys.argv[1], "w")))
        rate = rospy.Rate(5)
        while not rospy.is_shutdown():
            if rospy.get_time() >= 0.8:
                rospy.signal_shutdown("done")
            else:
                rate.sleep()
        rospy.sleep(1.0)  # after shutdown: ROSInterruptException, the run's normal end
    """, timeout=5.0)
    assert report.exception is None and report.shutdown == "signal_shutdown: done"
    assert data["t"] == pytest.approx(0.8)


def test_the_script_exception_points_at_its_own_line(tmp_path):
    report, _ = run(tmp_path, """
        import rospy
        from omtp_gazebo.msg import LogicalCameraImage

        def main():
            rospy.init_node("waiter")
            rospy.wait_for_message("/omtp/logical_camera_2", LogicalCameraImage, timeout=0.05)
            rospy.wait_for_message("/omtp/logical_camera_9", LogicalCameraImage, timeout=0.2)

        main()
    """, name="my_pick.py")
    assert report.exception.startswith("ROSException: timeout exceeded while waiting for message on topic "
                                       "/omtp/logical_camera_9 (at my_pick.py:8 in main)")
    assert report.traceback[-1].startswith("my_pick.py:8 in main: rospy.wait_for_message(")
    assert not report.ok and report.sim_time_s == pytest.approx(0.25, abs=0.06)


def test_services_by_the_course_names_and_clear_errors(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        from omtp_gazebo.msg import ConveyorBeltState
        from omtp_gazebo.srv import ConveyorBeltControl, VacuumGripperControl
        rospy.init_node("services")
        rospy.wait_for_service("/gripper2/control")
        out = {"gripper": rospy.ServiceProxy("gripper2/control", VacuumGripperControl)(True).success}
        belt = rospy.ServiceProxy("/omtp/conveyor/control", ConveyorBeltControl)
        out["belt_150"] = belt(ConveyorBeltState(150)).success
        out["belt_50"] = belt(state=ConveyorBeltState(power=50)).success
        try:
            rospy.ServiceProxy("/spawn_object_once", VacuumGripperControl)(True)
        except rospy.ServiceException as e:
            out["unknown"] = str(e)
        try:
            rospy.get_master()
        except NotImplementedError as e:
            out["unsupported"] = str(e)
        json.dump(out, open(sys.argv[1], "w"))
    """)
    assert report.ok
    assert data["gripper"] is True and data["belt_150"] is False and data["belt_50"] is True
    assert data["unknown"].startswith("service [/spawn_object_once] unavailable: this cell has ")
    assert "/gripper1/control" in data["unknown"] and "/omtp/conveyor/control" in data["unknown"]
    assert data["unsupported"].startswith("rospy.get_master is not supported")


def test_tf2_lookup_transform_matches_the_reference_and_raises_tf2_errors(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy, tf2_ros, tf2_geometry_msgs
        from geometry_msgs.msg import PoseStamped
        rospy.init_node("tf")
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        rospy.sleep(0.2)
        stamped = buffer.lookup_transform("robot2_base_link", "bin_1_base_link", rospy.Time(0))
        t = stamped.transform.translation
        out = {"bin_in_robot2": [t.x, t.y, t.z]}
        try:
            buffer.lookup_transform("world", "bin_9_base_link", rospy.Time(0))
        except tf2_ros.LookupException as e:
            out["lookup"] = str(e)
        try:
            buffer.lookup_transform("world", "bin_1_base_link", rospy.Time(100))
        except tf2_ros.ExtrapolationException:
            out["extrapolation"] = True
        pose = PoseStamped()
        pose.header.frame_id = "bin_1_base_link"
        pose.pose.orientation.w = 1.0
        stamped = buffer.lookup_transform("world", "bin_1_base_link", rospy.Time(0))
        p = tf2_geometry_msgs.do_transform_pose(pose, stamped).pose.position
        out["bin_in_world"] = [p.x, p.y, p.z]
        json.dump(out, open(sys.argv[1], "w"))
    """)
    assert report.ok
    np.testing.assert_allclose(data["bin_in_robot2"], [-0.70, 0.20, -0.70], atol=0.01)  # reference values
    np.testing.assert_allclose(data["bin_in_world"], [-8.0, -2.2, 0.0], atol=1e-9)
    assert "unknown frame 'bin_9_base_link'" in data["lookup"] and data["extrapolation"]


def test_the_ros_names_are_on_the_path_for_the_script_only(tmp_path):
    path_before = list(sys.path)
    ros_names = ("rospy", "moveit_commander", "geometry_msgs")
    # A real ROS 2 package of the same name (ros2 tests in this process) is not the run's.
    modules_before = {name for name in sys.modules if name.split(".")[0] in ros_names}
    report, _ = run(tmp_path, """
        import rospy, moveit_commander, tf2_ros, geometry_msgs.msg, std_srvs.srv, omtp_gazebo.srv
        rospy.init_node("imports")
    """)
    assert report.ok and sys.path == path_before
    assert {name for name in sys.modules if name.split(".")[0] in ros_names} == modules_before
    import omtp_drake.ros  # noqa: F401  (importing the project adds no ROS names)

    with pytest.raises(ModuleNotFoundError):
        import rospy  # noqa: F401


def test_two_runs_of_a_script_give_the_same_report(tmp_path):
    source = """
        import rospy
        from omtp_gazebo.msg import LogicalCameraImage
        rospy.init_node("twice")
        seen = []
        rospy.Subscriber("/omtp/logical_camera_2", LogicalCameraImage, lambda m: seen.append(len(m.models)))
        rospy.sleep(1.2)
        rospy.loginfo("saw %s", seen)
        raise RuntimeError(f"saw {sum(seen)} models")
    """
    first = run(tmp_path, source)[0].to_dict()
    second = run(tmp_path, source)[0].to_dict()
    first.pop("wall_time_s"), second.pop("wall_time_s")
    assert first == second and first["exception"].startswith("RuntimeError: saw ")


def test_a_callback_that_raises_is_logged_recorded_and_delivery_goes_on(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        from std_msgs.msg import String
        rospy.init_node("bad_callback")
        got = []
        def on_chat(msg):
            got.append(msg.data)
            if msg.data == "two":
                raise ValueError("cannot handle two")
        rospy.Subscriber("chatter", String, on_chat)
        chatter = rospy.Publisher("/chatter", String, queue_size=10)
        for word in ("one", "two", "three"):
            chatter.publish(word)
            rospy.sleep(0.1)
        json.dump(got, open(sys.argv[1], "w"))
    """)
    assert data == ["one", "two", "three"]
    assert report.callback_errors == ["/chatter: ValueError: cannot handle two"] and not report.ok


def test_the_scripts_own_modules_are_forgotten_after_the_run_and_the_projects_kept(tmp_path):
    (tmp_path / "helpers.py").write_text("ANSWER = 42\n")
    report, data = run(tmp_path, """
        import json, sys
        import helpers
        import omtp_drake.ros.tf.transformations
        json.dump(helpers.ANSWER, open(sys.argv[1], "w"))
    """)
    assert report.ok and data == 42
    assert "helpers" not in sys.modules and "omtp_drake.ros.tf.transformations" in sys.modules


def test_a_latched_topic_gives_a_late_subscriber_its_last_message_once(tmp_path):
    report, data = run(tmp_path, """
        import json, sys
        import rospy
        from std_msgs.msg import String
        rospy.init_node("latch")
        early, late = [], []
        rospy.Subscriber("/status", String, lambda m: early.append(m.data))
        status = rospy.Publisher("/status", String, queue_size=1, latch=True)
        status.publish(String("ready"))
        rospy.sleep(0.2)
        rospy.Subscriber("/status", String, lambda m: late.append(m.data))
        rospy.sleep(0.2)
        json.dump([early, late], open(sys.argv[1], "w"))
    """)
    assert report.ok and data == [["ready"], ["ready"]]
