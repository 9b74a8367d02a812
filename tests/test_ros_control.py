"""ros_control on any robot: a pan-lift-tilt robot written here (transmissions, a controllers
YAML, a launch in the catkin layout) under ``ros-run --robot ... --controllers``; a
course-style rospy script sends a trajectory to ``/arm_controller/command`` and a position to
``/tilt_controller/command`` and counts ``/joint_states``. Plus the layer's rules: splines,
the YAML's forms and the refusals."""

import json
import logging
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.cell.joint_splines import JointSpline, Waypoint
from omtp_drake.errors import ConfigError, UnknownNameError, WorkspaceError
from omtp_drake.ros.run.runner import run_script
from omtp_drake.scenario.robot_world import with_robot
from omtp_drake.scenario.ros_control_parse import spawn_controllers, with_controllers
from omtp_drake.script import Cell
from omtp_drake.sim.ros_control import RosControl
from omtp_drake.sim.trajectory_request import RequestPoint, TrajectoryRequest

WS = Path(__file__).parent / "fixtures" / "control_ws"
PACKAGE = WS / "src" / "pan_lift_description"
ROBOT = PACKAGE / "urdf" / "pan_lift.urdf.xacro"
CONTROLLERS = PACKAGE / "config" / "controllers.yaml"
SCRIPT = WS / "scripts" / "move_pan_lift.py"
#: The trajectory the script sends (time_from_start, lift, pan) and the tilt position.
POINTS = [(1.0, 0.05, 0.6), (2.0, 0.1, 1.2)]
TILT = 0.4


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "result.json"
    spec = f"{CONTROLLERS} joint_state_controller arm_controller tilt_controller"
    report = run_script(SCRIPT, [str(out)], robot=ROBOT, controllers=[spec], timeout=20.0)
    return report, json.loads(out.read_text())


def _at(states, t):
    stamp, names, q = min(states, key=lambda s: abs(s[0] - t))
    return stamp, dict(zip(names, q))


def test_the_joints_reach_the_goal_within_the_controllers_tolerances(run):
    report, result = run
    assert report.exception is None
    _, end = _at(result["states"], result["end"])
    # constraints: pan_joint goal 0.01, lift_joint goal 0.005 (the YAML's)
    assert end["pan_joint"] == pytest.approx(POINTS[-1][2], abs=0.01)
    assert end["lift_joint"] == pytest.approx(POINTS[-1][1], abs=0.005)
    assert end["tilt_joint"] == pytest.approx(TILT, abs=0.01)


def test_the_trajectory_is_interpolated_between_its_points(run):
    _, result = run
    sent = result["sent"]
    # Positions only: linear segments from where the joints were (0) through each point.
    for dt, lift, pan in [(0.5, 0.025, 0.3), *POINTS, (1.5, 0.075, 0.9)]:
        _, q = _at(result["states"], sent + dt)
        assert q["pan_joint"] == pytest.approx(pan, abs=0.02)  # within the trajectory tolerance (0.2)
        assert q["lift_joint"] == pytest.approx(lift, abs=0.005)


def test_joint_states_name_every_joint_at_the_publish_rate(run):
    _, result = run
    stamps = np.array([s[0] for s in result["states"]])
    assert all(s[1] == ["pan_joint", "lift_joint", "tilt_joint"] for s in result["states"])
    # publish_rate: 25 (the YAML's): one message every 0.04 s of simulated time.
    assert np.allclose(np.diff(stamps), 0.04, atol=1e-6)
    assert len(stamps) == pytest.approx((result["end"] - stamps[0]) * 25 + 1, abs=1)


# ----------------------------------------------------------------------------- the layer


@pytest.fixture(scope="module")
def cell():
    scenario = with_robot(None, ROBOT)
    scenario.models[:] = spawn_controllers(scenario.models, str(CONTROLLERS))
    with Cell(scenario) as cell:
        yield cell


def test_a_refused_trajectory_keeps_what_plays(cell):
    control = RosControl(cell.station)
    arm = next(c for c in control.controllers if c.name == "arm_controller")
    context = cell.runtime.context
    before = control.desired(context, arm)[0]
    bad = [
        (("pan_joint",), (RequestPoint(1.0, (0.3,)),), "each of the controller's joints"),
        (("pan_joint", "elbow"), (RequestPoint(1.0, (0.3, 0.1)),), "'elbow'"),
        (("pan_joint", "lift_joint"), (RequestPoint(1.0, (0.3,)),), "1 positions for 2 joints"),
        (("pan_joint", "lift_joint"), (RequestPoint(1.0, (0, 0)), RequestPoint(0.5, (0, 0))), "increase"),
        (("pan_joint", "lift_joint"), (RequestPoint(1.0, (np.nan, 0)),), "not finite"),
    ]
    for names, points, message in bad:
        with pytest.raises(ConfigError, match=message):
            control.follow(context, arm, TrajectoryRequest(names, points))
    assert np.array_equal(control.desired(context, arm)[0], before)
    tilt = next(c for c in control.controllers if c.name == "tilt_controller")
    with pytest.raises(ConfigError, match="dimension of command"):
        control.forward(context, tilt, [0.1, 0.2])


def test_a_trajectory_with_velocities_is_cubic():
    spline = JointSpline.through([Waypoint(0.0, (0.0,), (0.0,)), Waypoint(2.0, (1.0,), (0.5,))])
    q, v = spline.sample(2.0 - 1e-9)
    assert q[0] == pytest.approx(1.0) and v[0] == pytest.approx(0.5, abs=1e-6)
    assert spline.sample(0.0)[1][0] == pytest.approx(0.0)
    assert spline.sample(5.0)[0][0] == 1.0 and spline.sample(5.0)[1][0] == 0.0  # held at rest after


def test_a_segment_is_linear_unless_both_ends_give_velocities():
    points = [Waypoint(0.0, (0.0,), (0.0,)), Waypoint(1.0, (1.0,)), Waypoint(2.0, (3.0,), (0.0,))]
    spline = JointSpline.through(points)
    assert spline.sample(0.5)[0][0] == pytest.approx(0.5) and spline.sample(0.5)[1][0] == pytest.approx(1.0)
    assert spline.sample(1.5)[0][0] == pytest.approx(2.0) and spline.sample(1.5)[1][0] == pytest.approx(2.0)


def test_a_trajectory_with_accelerations_is_quintic():
    points = [Waypoint(1.0, (0.0,), (0.0,), (0.0,)), Waypoint(2.0, (1.0,), (0.0,), (0.0,))]
    spline = JointSpline.through(points)
    h = 1e-5
    q = [spline.sample(t)[0][0] for t in (1.5 - h, 1.5, 1.5 + h)]
    assert q[1] == pytest.approx(0.5)  # symmetric
    v_end = spline.sample(2.0 - 1e-9)[1][0]
    assert v_end == pytest.approx(0.0, abs=1e-6)


def test_controllers_yaml_errors_name_the_file_and_the_value(tmp_path):
    scenario = with_robot(None, ROBOT)
    config = scenario.models[0].gazebo.ros_control
    assert config is not None and [j.command_interfaces for j in config.joints] == [
        ["position"],
        ["position"],
        ["effort"],
    ]
    cases = {
        "c:\n  type: position_controllers/Nope\n  joints: [pan_joint]\n": "type",
        "c:\n  type: effort_controllers/JointTrajectoryController\n  joints: [tilt_joint]\n": "no p gain",
        "c:\n  type: position_controllers/JointTrajectoryController\n  joints: [tilt_joint]\n": "effort",
        "c:\n  type: position_controllers/JointGroupPositionController\n  joints: [pan_joint]\n"
        "d:\n  type: position_controllers/JointPositionController\n  joint: pan_joint\n": "both claim",
        "c:\n  type: position_controllers/JointTrajectoryController\n  joints: [wheel]\n": "wheel",
        "c:\n  type: joint_state_controller/JointStateController\n": "'publish_rate' not set",
    }
    for text, message in cases.items():
        with pytest.raises((ConfigError, UnknownNameError), match=message):
            with_controllers(config, text, "bad.yaml")
    with pytest.raises(UnknownNameError, match="gripper_controller"):
        with_controllers(config, CONTROLLERS.read_text(), str(CONTROLLERS), ["gripper_controller"])


def test_a_bad_command_is_one_error_line_and_the_run_goes_on(tmp_path, caplog):
    script = tmp_path / "bad.py"
    script.write_text(
        "import rospy\n"
        "from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint\n"
        "rospy.init_node('bad')\n"
        "pub = rospy.Publisher('/arm_controller/command', JointTrajectory, queue_size=1)\n"
        "rospy.sleep(0.2)\n"
        "msg = JointTrajectory()\nmsg.joint_names = ['pan_joint']\n"
        "msg.points = [JointTrajectoryPoint(positions=[0.5], time_from_start=rospy.Duration(1.0))]\n"
        "pub.publish(msg)\nrospy.sleep(0.2)\n"
    )
    with caplog.at_level(logging.ERROR, logger="rospy"):
        report = run_script(script, robot=ROBOT, controllers=[f"{CONTROLLERS} arm_controller"], timeout=5.0)
    assert report.exception is None
    lines = [r.getMessage() for r in caplog.records if "arm_controller" in r.getMessage()]
    assert len(lines) == 1 and "each of the controller's joints" in lines[0]


# ----------------------------------------------------------------------------- a launch's spawners


def _launch_models(text: str, tmp_path: Path):
    from omtp_drake.launch.controller_spawners import start_spawned_controllers
    from omtp_drake.launch.own_cell import student_workspace
    from omtp_drake.launch.roslaunch import read_launch

    workspace = student_workspace([WS / "src"])
    launch_file = tmp_path / "spawn.launch"
    launch_file.write_text(text)
    launch = read_launch(launch_file, {}, workspace)
    return start_spawned_controllers(with_robot(None, ROBOT).models, launch)


def test_a_launch_files_rosparam_and_spawner_start_the_controllers(tmp_path):
    launch = (PACKAGE / "launch" / "pan_lift.launch").read_text()
    (model,) = _launch_models(launch, tmp_path)
    config = model.gazebo.ros_control
    assert [c.name for c in config.controllers] == [
        "joint_state_controller",
        "arm_controller",
        "tilt_controller",
    ]
    assert config.controllers[0].publish_rate == 25.0
    assert config.controllers[2].gains["tilt_joint"].p == 200.0
    stopped = launch.replace('args="joint_state_controller', 'args="--stopped joint_state_controller')
    assert not _launch_models(stopped, tmp_path)[0].gazebo.ros_control.controllers


def test_a_spawner_without_parameters_or_robot_is_one_line_naming_the_launch(tmp_path):
    launch = (PACKAGE / "launch" / "pan_lift.launch").read_text()
    no_params = launch.replace("<rosparam", "<!-- rosparam").replace(
        'command="load"/>', 'command="load"/ -->'
    )
    with pytest.raises(
        WorkspaceError, match=r"spawn.launch:\d+: spawner: controller 'joint_state_controller'"
    ):
        _launch_models(no_params, tmp_path)
    other_ns = launch.replace('name="controller_spawner"', 'name="controller_spawner" ns="robot2"')
    with pytest.raises(WorkspaceError, match="namespace '/robot2'"):
        _launch_models(other_ns, tmp_path)


# ------------------------------------------------------------------ follow_joint_trajectory (ROS 1)


def test_follow_joint_trajectory_goals_end_as_the_controller_judges_them(tmp_path):
    out = tmp_path / "goals.json"
    script = WS / "scripts" / "follow_joint_trajectory.py"
    report = run_script(script, [str(out)], robot=ROBOT, controllers=[str(CONTROLLERS)], timeout=20.0)
    assert report.exception is None
    seen = json.loads(out.read_text())
    reachable = seen["reachable"]
    assert (reachable["state"], reachable["error_code"]) == (3, 0)  # SUCCEEDED, SUCCESSFUL
    assert reachable["actual"] == pytest.approx([-0.5, 0.12], abs=0.005)  # the goal tolerances (0.01, 0.005)
    assert 1.5 <= reachable["took"] < 1.5 + 0.5 + 0.1  # the trajectory's end, within goal_time
    # The lift stops at its limit (0.15): aborted once it lags its trajectory tolerance (0.05).
    past = seen["past_limit"]
    assert (past["state"], past["error_code"]) == (4, -4) and "lift_joint" in past["error_string"]
    assert past["actual"][1] == pytest.approx(0.15, abs=0.005)
    wrong = seen["wrong_joint"]
    assert (wrong["state"], wrong["error_code"]) == (5, -2) and "'elbow_joint'" in wrong["error_string"]


# ------------------------------------------------------------------ effort and velocity interfaces

#: A horizontal arm (1 kg at 0.3 m) on a y-axis joint under gravity, effort-driven, and a
#: velocity-driven wrist (0.1 kg at 0.6 m): ``m g l`` = 3.53 N m on the shoulder at 0 rad.
ARM_URDF = """<robot name="pid_arm">
  <link name="world"/>
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="fixed" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 1"/></joint>
  <link name="arm"><inertial><origin xyz="0.3 0 0"/><mass value="1"/>
    <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="100" velocity="5"/></joint>
  <link name="hand"><inertial><mass value="0.1"/>
    <inertia ixx="0.0001" iyy="0.0001" izz="0.0001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="wrist" type="revolute"><parent link="arm"/><child link="hand"/><origin xyz="0.6 0 0"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <transmission name="t1"><type>transmission_interface/SimpleTransmission</type>
    <joint name="shoulder">
      <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface></joint>
    <actuator name="m1"><mechanicalReduction>1</mechanicalReduction></actuator></transmission>
  <transmission name="t2"><type>transmission_interface/SimpleTransmission</type>
    <joint name="wrist">
      <hardwareInterface>hardware_interface/VelocityJointInterface</hardwareInterface></joint>
    <actuator name="m2"><mechanicalReduction>1</mechanicalReduction></actuator></transmission>
  <gazebo><plugin name="control" filename="libgazebo_ros_control.so"/></gazebo>
</robot>"""
ARM_CONTROLLERS = """
shoulder_controller:
  type: effort_controllers/JointPositionController
  joint: shoulder
  pid: {{p: 100.0, d: 10.0, i: {i}, i_clamp: 10.0}}
wrist_controller:
  type: velocity_controllers/JointTrajectoryController
  joints: [wrist]
  gains: {{wrist: {{p: 10.0, d: 0.0, i: 0.0, i_clamp: 0.0}}}}
"""


def _pid_arm(tmp_path, i):
    robot = tmp_path / "pid_arm.urdf"
    robot.write_text(ARM_URDF)
    yaml_file = tmp_path / f"pid_{i}.yaml"
    yaml_file.write_text(ARM_CONTROLLERS.format(i=i))
    scenario = with_robot(None, robot)
    scenario.models[:] = spawn_controllers(scenario.models, str(yaml_file))
    return Cell(scenario)


@pytest.mark.parametrize("i", [0.0, 200.0])
def test_an_effort_pid_sags_by_gravity_over_p_and_its_integral_removes_the_sag(tmp_path, i):
    with _pid_arm(tmp_path, i) as cell:
        control = RosControl(cell.station)
        wrist = next(c for c in control.controllers if c.name == "wrist_controller")
        context = cell.runtime.context
        control.follow(context, wrist, TrajectoryRequest(("wrist",), (RequestPoint(1.0, (1.0,)),)))
        cell.runtime.advance_to(4.0)
        q, v = control.system.measured(context, "pid_arm", ["shoulder", "wrist"])
    # y-axis joint: gravity on the arm pulls q positive (x toward -z); the PD's p balances it.
    sag = (1.0 * 0.3 + 0.1 * 0.6) * 9.81 / 100.0  # arm and hand: m g l over p
    if i == 0:
        assert q[0] == pytest.approx(sag, rel=0.05)
    else:
        assert abs(q[0]) < 1e-3
    assert q[1] == pytest.approx(1.0, abs=1e-3) and abs(v[1]) < 1e-3


# ------------------------------------------------------------------ ROS 2: declared and active controllers

ROS2_YAML = """
controller_manager:
  ros__parameters:
    update_rate: 50
    arm_controller: {type: joint_trajectory_controller/JointTrajectoryController}
    forward_position_controller: {type: forward_command_controller/ForwardCommandController}
    joint_state_broadcaster: {type: joint_state_broadcaster/JointStateBroadcaster}
arm_controller:
  ros__parameters: {joints: [a, b], command_interfaces: [position]}
forward_position_controller:
  ros__parameters: {joints: [a, b], interface_name: position}
"""


def test_ros2_controllers_are_activated_in_order_and_a_conflict_is_one_warning(tmp_path, caplog):
    import xml.etree.ElementTree as ET

    from omtp_drake.scenario.ros_control_parse import parse_ros_control, spawned_only

    yaml_file = tmp_path / "controllers.yaml"
    yaml_file.write_text(ROS2_YAML)
    joints = "".join(
        f'<joint name="{j}"><command_interface name="position"/><state_interface name="position"/></joint>'
        for j in "ab"
    )
    urdf = (
        f'<robot name="r"><ros2_control name="s" type="system">{joints}</ros2_control><gazebo>'
        f'<plugin filename="libgazebo_ros2_control.so" name="c"><parameters>{yaml_file}</parameters>'
        "</plugin></gazebo></robot>"
    )
    with caplog.at_level(logging.WARNING, logger="gazebo"):
        config = parse_ros_control(ET.fromstring(urdf), "r.urdf")
    assert config.update_rate == 50.0
    assert [c.name for c in config.controllers] == ["arm_controller", "joint_state_broadcaster"]
    assert "'forward_position_controller' not activated: 'arm_controller' holds" in caplog.text
    # A launch's spawners pick among the declared ones.
    spawned = spawned_only(
        config, ["joint_state_broadcaster", "forward_position_controller"], "bringup.launch.py"
    )
    assert [c.name for c in spawned.controllers] == ["joint_state_broadcaster", "forward_position_controller"]
    with pytest.raises(ConfigError, match="resource conflict"):
        spawned_only(config, ["arm_controller", "forward_position_controller"], "bringup.launch.py")
    with pytest.raises(UnknownNameError, match="gripper_controller"):
        spawned_only(config, ["gripper_controller"], "bringup.launch.py")


def test_view_json_lists_the_ros_control_plugin_and_its_controllers():
    from omtp_drake.viz.model_view import model_info

    robot = WS / "src" / "two_joint_ros2" / "urdf" / "two_joint.urdf.xacro"
    (plugin,) = [
        p for p in model_info(with_robot(None, robot).models[0])["plugins"] if p["kind"] == "ros_control"
    ]
    assert plugin["plugin"] == "gazebo_ros2_control" and plugin["update_rate"] == 100.0
    assert [c["name"] for c in plugin["controllers"]] == ["arm_controller", "joint_state_broadcaster"]
    assert [j["initial_position"] for j in plugin["joints"]] == [0.3, 0.05]


def test_a_state_only_joint_is_reported_and_an_unlisted_transmission_is_free(tmp_path):
    yaml_file = tmp_path / "c.yaml"
    yaml_file.write_text(
        "controller_manager:\n  ros__parameters:\n"
        "    jsb: {type: joint_state_broadcaster/JointStateBroadcaster}\n"
        "    fwd: {type: forward_command_controller/ForwardCommandController}\n"
        "fwd:\n  ros__parameters: {joints: [shoulder], interface_name: position}\n"
    )
    urdf = ARM_URDF.replace(
        '<gazebo><plugin name="control" filename="libgazebo_ros_control.so"/></gazebo>',
        '<ros2_control name="s" type="system">'
        '<joint name="shoulder"><command_interface name="position"/>'
        '<state_interface name="position"/></joint>'
        '<joint name="wrist"><state_interface name="position"/></joint></ros2_control>'
        f'<gazebo><plugin filename="libgazebo_ros2_control.so" name="c"><parameters>{yaml_file}</parameters>'
        "</plugin></gazebo>",
    )
    robot = tmp_path / "r.urdf"
    robot.write_text(urdf)
    with Cell(with_robot(None, robot)) as cell:
        control = RosControl(cell.station)
        jsb = next(c for c in control.controllers if c.name == "jsb")
        fwd = next(c for c in control.controllers if c.name == "fwd")
        control.forward(cell.runtime.context, fwd, [0.5])
        cell.runtime.advance_to(1.0)
        sample = control.joint_state(cell.runtime.context, jsb)
    assert sample.names == ("shoulder", "wrist")
    assert sample.position[0] == pytest.approx(0.5, abs=1e-3)
    # The wrist (its transmission's actuator unlisted) hangs free: no effort on it.
    assert sample.effort[1] == 0.0


def test_a_missing_ros2_parameters_file_is_one_warning_and_no_controllers(caplog):
    import xml.etree.ElementTree as ET

    from omtp_drake.scenario.ros_control_parse import parse_ros_control

    urdf = (
        '<robot name="r"><ros2_control name="s" type="system"><joint name="a">'
        '<command_interface name="position"/></joint></ros2_control><gazebo>'
        '<plugin filename="libgazebo_ros2_control.so" name="c"><parameters>/nowhere/c.yaml</parameters>'
        "</plugin></gazebo></robot>"
    )
    with caplog.at_level(logging.WARNING, logger="gazebo"):
        config = parse_ros_control(ET.fromstring(urdf), "r.urdf")
    assert config.controllers == [] and [j.name for j in config.joints] == ["a"]
    assert "r.urdf: gazebo_ros2_control <parameters> '/nowhere/c.yaml': no such file" in caplog.text


def test_a_launch_spawns_the_robot_and_its_controllers_and_the_script_drives_them(tmp_path):
    """pan_lift.launch as roslaunch runs it: spawn_model puts the robot (none of the course's
    pieces) in the empty world, <rosparam> and controller_manager's spawner start its
    controllers; the course-style script's trajectory on /arm_controller/command is followed."""
    from omtp_drake.launch import own_cell

    cell = own_cell("pan_lift_description pan_lift.launch", workspace=[WS / "src"], environ={})
    (model,) = cell.scenario.models
    assert [c.name for c in model.gazebo.ros_control.controllers] == [
        "joint_state_controller",
        "arm_controller",
        "tilt_controller",
    ]
    out = tmp_path / "result.json"
    report = run_script(SCRIPT, [str(out)], scenario=cell.scenario, timeout=20.0)
    assert report.exception is None
    result = json.loads(out.read_text())
    _, end = _at(result["states"], result["end"])
    assert end["pan_joint"] == pytest.approx(POINTS[-1][2], abs=0.01)
    assert end["lift_joint"] == pytest.approx(POINTS[-1][1], abs=0.005)
    assert end["tilt_joint"] == pytest.approx(TILT, abs=0.01)
