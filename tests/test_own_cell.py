"""A student's own cell: the course's launch files, world, xacro and Gazebo plugins, laid out
as the course's catkin workspace (fixtures written here, ``tests/fixtures/catkin_ws``), built
through the loader: the same cell as the built-in scenarios, frame by frame and in behaviour."""

from __future__ import annotations

import dataclasses
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from fixture_reports import assert_as_recorded
from pydrake.math import RollPitchYaw
from pydrake.multibody.tree import FrameIndex, JointIndex

from omtp_drake.launch import own_cell, student_workspace
from omtp_drake.launch.urdf_model import UrdfModel
from omtp_drake.scenario import load_scenario
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.workspace import expand_xacro_in

FIXTURES = Path(__file__).resolve().parent / "fixtures"
WORKSPACE = FIXTURES / "catkin_ws" / "src"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


@pytest.fixture(scope="module")
def course():
    return own_cell(LAUNCH, workspace=[WORKSPACE], environ={})


def _frames_and_joints(scenario):
    """The frames of ``scenario``'s cell in world, and its joints' positions, at t = 0."""
    runtime = FactoryRuntime(scenario)
    plant = runtime.station.plant
    context = plant.GetMyContextFromRoot(runtime.context)
    frames = {}
    for i in range(plant.num_frames()):
        frame = plant.get_frame(FrameIndex(i))
        frames[frame.name()] = frame.CalcPoseInWorld(context)
    q = {}
    for i in range(plant.num_joints()):
        joint = plant.get_joint(JointIndex(i))
        if joint.num_positions() == 1:
            q[joint.name()] = float(joint.GetOnePosition(context))
    return frames, q


@pytest.fixture(scope="module")
def built_in_frames():
    """The built-in omtp_factory's frames in world, and its joints' positions (Home)."""
    return _frames_and_joints(load_scenario("omtp_factory"))


def _scenario_fields(scenario):
    return {
        f.name: repr(getattr(scenario, f.name))
        for f in dataclasses.fields(scenario)
        if f.name not in ("name", "description", "frames")
    }


def test_the_course_launch_is_the_built_in_lecture6_assignment1(course):
    """Same robots, cameras, bins, belt, beam, wall, gripper rule and spawner (wired behind
    /spawn_object_once with the spawn_object_once node, as the course's launch wires it);
    the built-in adds the part the slides' `rosservice call /spawn_object_once` spawns."""
    built_in = dataclasses.replace(load_scenario("lecture6_assignment1"), parts=[])
    # The launch's spawner is the course's plugin, its one box where the built-in spawns.
    (box,) = course.scenario.spawner.objects
    assert (box.name, box.xyz, box.rpy) == ("box", built_in.spawner.xyz, [0.0, 0.0, 0.0])
    as_built_in = dataclasses.replace(course.scenario.spawner, objects=[])
    # The pedestals and the bin are the launch's own, as its files write them (the built-in's
    # are the catalogue's of the same size): model entries the arms stand on, the bin's inside
    # measured on its collision meshes, the catalogue bin's; the cameras' camera.dae housings
    # are theirs too, on the cell's camera frames (the built-in draws its stand-in).
    pedestals = {r.pedestal_model for r in course.scenario.robots}
    assert pedestals == {"robot1_pedestal", "robot2_pedestal"}
    housings = {"logical_camera_1_own", "logical_camera_2_own"}
    assert {m.name for m in course.scenario.models} == pedestals | {"bin_1_"} | housings
    assert not any(c.housing for c in course.scenario.cameras)
    (bin_1,) = course.scenario.bins
    assert bin_1.model == "bin_1_"
    np.testing.assert_allclose(bin_1.walls, [0.19, 0.19, 0.12, 0.475], atol=1e-6)
    same = dataclasses.replace(
        course.scenario,
        spawner=as_built_in,
        models=[],
        robots=[dataclasses.replace(r, pedestal_model="") for r in course.scenario.robots],
        bins=[dataclasses.replace(b, model="", walls=[]) for b in course.scenario.bins],
        cameras=[dataclasses.replace(c, housing=True) for c in course.scenario.cameras],
    )
    assert _scenario_fields(same) == _scenario_fields(built_in)
    # (frames: the links of the files that none of the cell's pieces has; see below)
    assert course.scenario.spawner.start_service == "/spawn_object_once"
    assert course.scenario.spawner.stop_node
    assert course.scenario.cameras[0].name == "logical_camera_1"
    assert course.moveit_config is None  # no omtp_moveit_config of the student's: the cell's own


def _compare(frames, built_in, at_least):
    common = sorted(set(frames) & set(built_in))
    assert len(common) >= at_least, common
    for name in common:
        X_a, X_b = frames[name], built_in[name]
        assert np.linalg.norm(X_a.translation() - X_b.translation()) < 1e-3, name
        assert abs((X_a.rotation().inverse() @ X_b.rotation()).ToAngleAxis().angle()) < 1e-3, name
    return common


def test_every_frame_the_spawned_files_give_is_within_1_mm_of_the_built_in_cell(course, built_in_frames):
    frames, q = built_in_frames
    common = _compare(course.frames(q), frames, at_least=30)
    for name in (
        "robot1_tool0",
        "vacuum_gripper2_suction_cup",
        "bin_1_drop_point",
        "break_beam_optical_link",
        "break_beam_base_link",
        "robot2_pedestal_link",
        "robot1_wrist_3_link",
    ):
        assert name in common


def test_every_link_of_the_spawned_files_is_a_frame_of_the_cell_built_from_them(course):
    """Links none of the cell's pieces has (the pedestals' and the workcell's world_interface,
    the workcell, the break beam's world_interface) are the scenario's extra frames."""
    frames, q = _frames_and_joints(course.scenario)
    links = course.frames(q)
    assert {"world_interface", "workcell", "break_beam_world_interface"} <= set(links)
    missing = sorted(set(links) - set(frames))
    assert not missing, missing
    _compare(links, frames, at_least=len(links))
    assert abs(RollPitchYaw(frames["workcell"].rotation()).yaw_angle() - math.pi / 2) < 1e-9


def test_lecture1_factory_urdf_puts_every_frame_where_the_built_in_cell_has_it(built_in_frames):
    frames, q = built_in_frames
    workspace = student_workspace([WORKSPACE], environ={})
    text = expand_xacro_in(workspace, WORKSPACE / "omtp_support" / "urdf" / "omtp_factory.xacro")
    model = UrdfModel.from_text(text, "omtp_factory.xacro")
    assert model.root == "world"
    _compare(model.link_poses(q), frames, at_least=30)


def test_the_same_behaviour_on_a_fixed_seed(course):
    """The loaded cell and the built-in one, the same part on the belt under camera 1: the
    same camera images, beam, part poses and ledger after the belt ran."""
    from omtp_drake.script import Cell

    built_in = dataclasses.replace(load_scenario("lecture6_assignment1"), seed=11)
    loaded = dataclasses.replace(course.scenario, seed=11, parts=built_in.parts)
    records = []
    for scenario in (loaded, built_in):
        cell = Cell(scenario, auto_spawn=False)
        try:
            cell.wait(0.3)
            seen_before = cell.camera("logical_camera_1").parts()
            cell.set_conveyor_power(100.0)
            cell.wait(4.0)
            ledger = cell.ledger().to_dict()
            record = (
                {k: v.pose for k, v in seen_before.items()},
                cell.break_beam(),
                cell.part_pose("object_1").GetAsMatrix4(),
                {k: v for k, v in ledger.items() if k != "time"},
                cell.camera("logical_camera_2").image(),
            )
        finally:
            cell.close()
        records.append(record)
    a, b = records
    assert "object_1" in a[0]
    assert repr(a[0]) == repr(b[0]) and a[1] == b[1] and repr(a[4]) == repr(b[4])
    np.testing.assert_array_equal(a[2], b[2])
    assert a[3] == b[3]
    assert a[2][1, 3] < 1.8 - 0.5  # the belt carried the part downstream


@pytest.fixture
def students_workspace(tmp_path):
    """The course's workspace with the student's assignment-4 edit: a bin next to robot 1."""
    src = tmp_path / "catkin_ws" / "src"
    shutil.copytree(WORKSPACE, src)
    shutil.copy(
        FIXTURES / "student_edits" / "spawn_static_world_objects.launch", src / "omtp_gazebo" / "launch"
    )
    return src


def test_a_students_bin_next_to_robot_1_is_in_the_cell(students_workspace):
    cell = own_cell(LAUNCH, workspace=[students_workspace], environ={})
    bins = {b.name: b.xyz for b in cell.scenario.bins}
    assert bins == {"bin_1": [-8.0, -2.2, 0.0], "bin_2": [-0.1, 2.5, 0.0]}


def test_a_course_style_robot_1_script_drops_the_box_into_the_students_bin(students_workspace, tmp_path):
    """ros-run --launch 'omtp_lecture6 lecture6_assignment1.launch' --workspace WS: the script
    asks /spawn_object_once for a box, picks it under camera 1 and drops it into bin_2."""
    import json

    from omtp_drake.cli import main

    script = FIXTURES / "student_edits" / "lecture6_assignment4_robot1.py"
    out = tmp_path / "report.json"
    argv = ["ros-run", str(script), "--launch", LAUNCH, "--workspace", str(students_workspace)]
    assert main([*argv, "--timeout", "120", "--json", str(out), "-q"]) == 0
    report = json.loads(out.read_text())
    assert report["exception"] is None, report["traceback"]
    assert report["scenario"] == "lecture6_assignment1"
    assert report["ledger"]["in_bin"] == {"bin_1": 0, "bin_2": 1}
    assert report["ledger"]["parts"] == {"object_1": "in_bin:bin_2"}
    assert_as_recorded("student_edits lecture6_assignment4_robot1.py", report)


def test_the_python_api_takes_the_launch_and_the_workspace():
    from omtp_drake.script import Cell

    with Cell(launch=LAUNCH, workspace=[WORKSPACE], auto_spawn=False) as cell:
        assert [c.name for c in cell.scenario.cameras] == ["logical_camera_1", "logical_camera_2"]
        cell.wait(0.2)
        assert cell.break_beam() is False and cell.conveyor_power() == 0.0


def test_commands_take_launch_and_workspace_instead_of_a_scenario(capsys):
    from omtp_drake.cli import main

    args = ["tf-echo", "--launch", LAUNCH, "--workspace", str(WORKSPACE), "world", "bin_1_drop_point"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    assert "- Translation: [-8.000, -2.200, 1.000]" in out
    assert "omtp-drake: warning: " in err and "0.695 m high" in err  # the course's robot-2 pedestal


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["tf-echo", "--launch", LAUNCH, "world", "bin_1_base_link"], "package 'omtp_lecture6' not found"),
        (["tf-echo", "omtp_factory", "world", "x", "--launch", LAUNCH], "give one of a scenario"),
        (["tf-echo", "world", "x"], "give a scenario (name or file), --launch"),
        (["tf-echo", "omtp_factory", "world", "x", "--workspace", "/tmp"], "--workspace goes with --launch"),
    ],
)
def test_command_option_errors_are_one_line_and_exit_2(capsys, argv, expected):
    from omtp_drake.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert expected in err and err.count("\n") == 1


def test_a_launchs_python_node_runs_unchanged_in_the_ros_run_session(tmp_path):
    """The node starts as roslaunch starts it (its args, its name, its remappings) before the
    script, and its subscriber keeps serving while the script runs."""
    from omtp_drake.cli import main

    src = tmp_path / "src"
    shutil.copytree(WORKSPACE, src)
    (src / "omtp_lecture6" / "scripts").mkdir(exist_ok=True)  # git keeps no empty folder
    (src / "omtp_lecture6" / "scripts" / "echo_node.py").write_text(
        "import sys\nimport rospy\nfrom std_msgs.msg import String\n\n"
        "def on_ping(msg, pub):\n    pub.publish(String(data=msg.data + ' from ' + rospy.get_name()))\n\n"
        "if __name__ == '__main__':\n    rospy.init_node('echo')\n"
        "    pub = rospy.Publisher('answer', String, queue_size=1, latch=True)\n"
        "    rospy.Subscriber('ping', String, on_ping, callback_args=pub)\n"
        "    params = ' gain %s %s' % (rospy.get_param('~gain'), rospy.get_param('~limits/max'))\n"
        "    pub.publish(String(data='args ' + ' '.join(rospy.myargv()[1:]) + params))\n"
        "    rospy.spin()\n"
    )
    launch = src / "omtp_lecture6" / "launch" / "lecture6_assignment1.launch"
    launch.write_text(
        launch.read_text().replace(
            "</launch>",
            '  <node name="my_echo" pkg="omtp_lecture6" type="echo_node.py" args="--speed 2">\n'
            '    <remap from="answer" to="/echo_answer"/>\n    <param name="gain" value="0.5"/>\n'
            "    <rosparam>limits: {max: 3}</rosparam>\n  </node>\n</launch>",
        )
    )
    script = tmp_path / "ask.py"
    out = tmp_path / "heard.txt"
    script.write_text(
        "import sys\nimport rospy\nfrom std_msgs.msg import String\n"
        "rospy.init_node('asker')\n"
        "first = rospy.wait_for_message('/echo_answer', String, timeout=2.0).data\n"
        "pub = rospy.Publisher('/ping', String, queue_size=1)\nrospy.sleep(0.5)\n"
        "pub.publish(String(data='hello'))\n"
        "second = rospy.wait_for_message('/echo_answer', String, timeout=2.0).data\n"
        "open(sys.argv[1], 'w').write(first + '\\n' + second)\n"
    )
    argv = ["ros-run", str(script), str(out), "--launch", LAUNCH, "--workspace", str(src), "-q"]
    assert main([*argv, "--timeout", "20"]) == 0
    assert out.read_text().splitlines() == ["args --speed 2 gain 0.5 3", "hello from /my_echo"]


def test_a_node_that_loops_before_spinning_is_one_error(tmp_path, capsys):
    from omtp_drake.cli import main

    src = tmp_path / "src"
    shutil.copytree(WORKSPACE, src)
    (src / "omtp_lecture6" / "scripts").mkdir(exist_ok=True)  # git keeps no empty folder
    (src / "omtp_lecture6" / "scripts" / "looper.py").write_text(
        "import rospy\nrospy.init_node('looper')\nwhile not rospy.is_shutdown():\n    rospy.sleep(0.1)\n"
    )
    launch = src / "omtp_lecture6" / "launch" / "lecture6_assignment1.launch"
    launch.write_text(
        launch.read_text().replace(
            "</launch>", '<node name="looper" pkg="omtp_lecture6" type="looper.py"/></launch>'
        )
    )
    script = tmp_path / "noop.py"
    script.write_text("import rospy\nrospy.init_node('noop')\n")
    assert main(["ros-run", str(script), "--launch", LAUNCH, "--workspace", str(src), "-q"]) == 2
    err = capsys.readouterr().err.splitlines()[-1]
    assert "looper.py __name:=looper: failed to start" in err and "waits or sleeps before rospy.spin()" in err


def test_built_in_lecture6_assignment1_has_spawn_object_once_as_the_courses_launch(tmp_path):
    """/spawn_object_once starts the belt's spawner (a box under camera 1 one period later);
    the course's spawn_object_once node stops it while an object is in the world."""
    from omtp_drake.ros.run.runner import run_script
    from omtp_drake.scenario import scenario_document, scenario_text

    script = tmp_path / "spawn.py"
    script.write_text(
        "import rospy\nfrom std_srvs.srv import Empty\nrospy.init_node('spawn')\n"
        "rospy.ServiceProxy('/spawn_object_once', Empty)()\nrospy.sleep(2.0)\n"
    )
    with_part = run_script(script, scenario="lecture6_assignment1", timeout=10.0)
    assert with_part.exception is None and with_part.ledger["parts"] == {
        "object_1": "on_belt"
    }  # the placed one
    assert "object_1 is in the world" in with_part.empty_spawn_calls[0]
    empty = tmp_path / "empty_belt.yaml"
    empty.write_text(scenario_text({**scenario_document("lecture6_assignment1"), "parts": []}))
    report = run_script(script, scenario=empty, timeout=10.0)
    assert report.exception is None and report.ledger["spawned"] == 1 and not report.empty_spawn_calls
    assert report.ledger["parts"] == {"object_1": "on_belt"}


def test_a_camera_the_student_places_elsewhere_is_there_in_the_cell(tmp_path):
    src = tmp_path / "src"
    shutil.copytree(WORKSPACE, src)
    world = src / "omtp_gazebo" / "worlds" / "lecture6_assignment1.world"
    world.write_text(world.read_text().replace("-8.3 -1.23 1.8 0 1.5708 0", "-8.0 -2.2 1.9 0 1.5708 0.3"))
    cell = own_cell(LAUNCH, workspace=[src], environ={})
    frames, _ = _frames_and_joints(cell.scenario)
    X_WC = frames["logical_camera_2_frame"]
    np.testing.assert_allclose(X_WC.translation(), [-8.0, -2.2, 1.9], atol=1e-9)
    R_expected = RollPitchYaw([0.0, 1.5708, 0.3]).ToRotationMatrix().matrix()
    np.testing.assert_allclose(X_WC.rotation().matrix(), R_expected, atol=1e-9)
