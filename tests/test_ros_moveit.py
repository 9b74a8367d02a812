"""MoveIt commander through ros-run: targets, plans, execution, Cartesian paths, the action."""

import json
import textwrap

import numpy as np
import pytest

from omtp_drake.ros import run_script

A4 = "lecture6_assignment4"

MOVES = """
    import json, sys
    import moveit_commander, moveit_msgs.msg, rospy
    moveit_commander.roscpp_initialize(sys.argv)
    rospy.init_node("moves")
    group = moveit_commander.MoveGroupCommander("robot2")
    out = {"eef": group.get_end_effector_link(), "frame": group.get_planning_frame(),
           "named": group.get_named_targets()}
    group.set_named_target("R2Place")
    out["place_ok"] = group.go(wait=True)
    group.stop()
    out["place_q"] = group.get_current_joint_values()
    try:
        group.set_joint_value_target([0, 0, 0, 0, 0, 4.0])
    except moveit_commander.MoveItCommanderException as e:
        out["out_of_bounds"] = str(e)
    group.set_named_target("R2Home")
    planned = group.plan()
    if isinstance(planned, tuple):
        out["plan_shape"] = [type(x).__name__ for x in planned]
    else:
        out["plan_shape"] = type(planned).__name__
    trajectory = planned[1] if isinstance(planned, tuple) else planned
    out["executed"] = group.execute(trajectory, wait=True)
    pose = group.get_current_pose().pose
    out["home_cup"] = [pose.position.x, pose.position.y, pose.position.z]
    start = [pose.position.x, pose.position.y, pose.position.z]
    waypoint = group.get_current_pose().pose
    waypoint.position.z -= 0.2
    plan, fraction = group.compute_cartesian_path([waypoint], 0.01, 0.0)
    out["fraction_noetic"] = fraction
    import actionlib
    client = actionlib.SimpleActionClient("execute_trajectory", moveit_msgs.msg.ExecuteTrajectoryAction)
    client.wait_for_server()
    client.send_goal(moveit_msgs.msg.ExecuteTrajectoryGoal(trajectory=plan))
    client.wait_for_result()
    out["action_code"] = client.get_result().error_code.val
    p = group.get_current_pose().pose.position
    out["after_descent"] = [p.x, p.y, p.z]
    waypoint.position.z += 0.2
    plan, fraction = group.compute_cartesian_path([waypoint], 0.01)  # MoveIt 1.1.15+
    out["fraction_new"] = fraction
    out["up_ok"] = group.execute(plan)
    group.set_pose_target([-8.0, -1.5, 3.0, 0.0, 0.0, 0.0])  # x, y, z, roll, pitch, yaw: out of reach
    out["unreachable_go"] = group.go()
    planned = group.plan()
    if isinstance(planned, tuple):
        out["unreachable_plan"] = [planned[0], len(planned[1].joint_trajectory.points), planned[3].val]
    json.dump(out, open(sys.argv[1], "w"))
"""


@pytest.mark.parametrize("moveit", ["noetic", "melodic"])
def test_move_group_targets_plans_and_cartesian_paths(tmp_path, moveit):
    script = tmp_path / "moves.py"
    script.write_text(textwrap.dedent(MOVES))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=A4, moveit=moveit)
    assert report.exception is None and report.collisions == []
    data = json.loads(out.read_text())
    assert data["eef"] == "vacuum_gripper2_suction_cup" and data["frame"] == "world"
    assert {"R2Home", "R2Place", "R2PreGrasp", "R2Up"} <= set(data["named"])
    assert data["place_ok"] is True
    np.testing.assert_allclose(data["place_q"], [2.5952, -1.161, 0.7512, -1.2293, -1.5708, 0.0], atol=1e-3)
    assert "wrist_3_joint of robot2 at 4.0000 rad is outside" in data["out_of_bounds"]
    if moveit == "noetic":
        assert data["plan_shape"] == ["bool", "RobotTrajectory", "float", "MoveItErrorCodes"]
    else:
        assert data["plan_shape"] == "RobotTrajectory"
    assert data["executed"] is True
    np.testing.assert_allclose(data["home_cup"], [-8.287, -1.609, 1.122], atol=2e-3)  # the reference's
    assert data["fraction_noetic"] == 1.0 and data["fraction_new"] == 1.0 and data["up_ok"] is True
    assert data["action_code"] == 1  # SUCCESS
    np.testing.assert_allclose(data["after_descent"], np.add(data["home_cup"], [0, 0, -0.2]), atol=2e-3)
    assert data["unreachable_go"] is False  # MoveIt's way: False, the reason logged
    if moveit == "noetic":
        assert data["unreachable_plan"] == [False, 0, -31]  # an empty trajectory, NO_IK_SOLUTION


SCENE = """
    import json, sys
    import moveit_commander, rospy
    from geometry_msgs.msg import PoseStamped
    rospy.init_node("scene")
    scene = moveit_commander.PlanningSceneInterface()
    group = moveit_commander.MoveGroupCommander("robot2")
    box = PoseStamped()
    box.header.frame_id = "bin_1_base_link"
    box.pose.position.x, box.pose.position.y, box.pose.position.z = -0.035, 0.105, 1.25
    box.pose.orientation.w = 1.0
    scene.add_box("lid", box, size=(0.3, 0.3, 0.3))  # where R2Place puts the cup
    out = {"known": scene.get_known_object_names()}
    group.set_named_target("R2Place")
    out["blocked"] = group.go()
    scene.remove_world_object("lid")
    out["free"] = group.go()
    scene.attach_box("vacuum_gripper2_suction_cup", "tool", size=(0.05, 0.05, 0.3))
    attached = scene.get_attached_objects()
    out["attached"] = {k: [v.link_name, v.object.primitives[0].dimensions] for k, v in attached.items()}
    scene.remove_attached_object("vacuum_gripper2_suction_cup", "tool")
    out["after"] = [scene.get_known_object_names(), list(scene.get_attached_objects())]
    json.dump(out, open(sys.argv[1], "w"))
"""


def test_planning_scene_interface_adds_named_obstacles(tmp_path, caplog):
    script = tmp_path / "scene.py"
    script.write_text(textwrap.dedent(SCENE))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=A4)
    assert report.ok
    data = json.loads(out.read_text())
    assert data["known"] == ["lid"] and data["blocked"] is False and data["free"] is True
    assert "lid" in caplog.text  # the failed plan names the box by its name
    assert data["attached"] == {"tool": ["vacuum_gripper2_suction_cup", [0.05, 0.05, 0.3]]}
    assert data["after"] == [["tool"], []]  # detached: back in the world, as MoveIt does


def test_callbacks_run_while_the_main_thread_waits_for_a_move(tmp_path):
    """As rospy's callback threads do while ``go()`` blocks: the camera's callbacks run
    at their times during the move, in order, not all after it."""
    script = tmp_path / "during.py"
    script.write_text(textwrap.dedent("""
        import json, sys
        import moveit_commander, rospy
        from omtp_gazebo.msg import LogicalCameraImage
        rospy.init_node("during")
        group = moveit_commander.MoveGroupCommander("robot2")
        times = []
        on_image = lambda m: times.append(rospy.get_time())
        rospy.Subscriber("/omtp/logical_camera_2", LogicalCameraImage, on_image)
        start = rospy.get_time()
        group.set_named_target("R2Place")
        group.go(wait=True)
        json.dump({"start": start, "end": rospy.get_time(), "times": times}, open(sys.argv[1], "w"))
    """))
    out = tmp_path / "out.json"
    assert run_script(script, [str(out)], scenario=A4).ok
    data = json.loads(out.read_text())
    times = np.array(data["times"])
    inside = times[(times > data["start"]) & (times < data["end"] - 0.2)]
    assert data["end"] - data["start"] > 1.0 and len(inside) >= 5
    assert np.all(np.diff(times) >= 0)


BAD_POSES = """
    import json, sys
    import moveit_commander, rospy
    import geometry_msgs.msg
    rospy.init_node("bad_poses")
    group = moveit_commander.MoveGroupCommander("robot2")
    out = {}
    try:
        group.set_pose_target([-8.0, -1.5, 1.0])  # forgot the orientation
    except moveit_commander.MoveItCommanderException as e:
        out["short_list"] = str(e)
    pose_goal = geometry_msgs.msg.Pose()
    pose_goal.position.x = float("nan")
    pose_goal.orientation.w = 1.0
    try:
        group.set_pose_target(pose_goal)
    except moveit_commander.MoveItCommanderException as e:
        out["nan_pose"] = str(e)
    json.dump(out, open(sys.argv[1], "w"))
"""


def test_a_bad_pose_target_raises_moveit_commander_exception(tmp_path):
    script = tmp_path / "bad_poses.py"
    script.write_text(textwrap.dedent(BAD_POSES))
    out = tmp_path / "out.json"
    report = run_script(script, [str(out)], scenario=A4)
    assert report.exception is None
    data = json.loads(out.read_text())
    assert "takes 6 numbers (x, y, z, roll, pitch, yaw) or 7" in data["short_list"]
    assert "got 3" in data["short_list"]
    assert "set_pose_target: the position" in data["nan_pose"] and "not finite" in data["nan_pose"]
