"""ROS 2 launch files (``.launch.py``) as ``ros2 launch`` runs them: the URDF tutorial's
``rsp_sim.launch.py`` (tests/fixtures/tutorial_ws, written here in the tutorial's form) with
and without ``world:=``, the launch API's rules (arguments, conditions, includes, groups,
timers, event handlers), what each node maps to, and the one-line refusals."""

from __future__ import annotations

import json
import logging
import sys
import textwrap
from pathlib import Path

import pytest
from test_ros2 import (
    SCRIPTS,
    domain,
    hold_domain,
    needs_ros2,
    run_cell_until,
)

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.launch_py import read_launch_py
from omtp_drake.launch.options import cell_of
from omtp_drake.workspace import Workspace

TUTORIAL_SRC = Path(__file__).parent / "fixtures" / "tutorial_ws" / "src"
PACKAGE = TUTORIAL_SRC / "slider_arm_description"
WORLD = PACKAGE / "worlds" / "two_crates.world"
LAUNCH = "slider_arm_description rsp_sim.launch.py"
__all__ = ["domain"]  # test_ros2's fixture: a ROS 2 domain of this test's own


@pytest.fixture(scope="module")
def empty_world():
    return cell_of(launch=LAUNCH, workspace=TUTORIAL_SRC)


def test_the_tutorial_launch_spawns_its_robot_in_the_empty_world(empty_world):
    models = {m.name: m for m in empty_world.scenario.models}
    assert list(models) == ["slider_arm"]
    robot = models["slider_arm"]
    assert robot.format == "urdf" and robot.xyz == [0.0, 0.0, 0.0]
    assert all(f'name="{j}"' in robot.description for j in ("slider_joint", "arm_joint", "camera_joint"))
    # Its gazebo_ros plugins are its model's (no "not in the cell" line); no node or process warns.
    assert empty_world.warnings == []
    assert [p.joint_names for p in robot.gazebo.joint_state_publishers] == [["slider_joint", "arm_joint"]]
    assert empty_world.controllers == []


def test_world_arg_loads_that_world_beside_the_robot():
    cell = cell_of(launch=f"{LAUNCH} world:={WORLD}", workspace=TUTORIAL_SRC)
    models = {m.name: m for m in cell.scenario.models}
    assert {"slider_arm", "crate_a", "crate_b"} <= set(models)
    assert models["crate_a"].xyz == pytest.approx([0.0, 1.5, 0.2])
    assert models["crate_b"].rpy == pytest.approx([0.0, 0.0, 0.5])


def test_a_world_that_is_no_file_is_one_error():
    with pytest.raises(
        WorkspaceError, match=r"gzserver\.launch\.py:\d+: gzserver world 'nowhere\.world': no such file"
    ):
        cell_of(launch=f"{LAUNCH} world:=nowhere.world", workspace=TUTORIAL_SRC)


def test_the_launch_api_leaves_sys_path_and_modules_as_they_were(empty_world):
    assert not any(name.split(".")[0] in ("launch", "launch_ros") for name in sys.modules)
    assert not any(p.endswith("shims") and "launch" in p for p in sys.path)


def _package(tmp_path: Path, text: str, name: str = "demo.launch.py") -> tuple[Path, Workspace]:
    folder = tmp_path / "src" / "demo"
    (folder / "launch").mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text("<package format='2'><name>demo</name></package>")
    path = folder / "launch" / name
    path.write_text(textwrap.dedent(text))
    return path, Workspace.from_dirs([tmp_path / "src"], environ={})


RULES = """\
from launch import LaunchDescription
from launch.actions import (DeclareLaunchArgument, ExecuteProcess, GroupAction, RegisterEventHandler,
                            TimerAction)
from launch.conditions import IfCondition, UnlessCondition
from launch.event_handlers import OnProcessExit
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    gui = LaunchConfiguration("gui")
    spawn = Node(package="gazebo_ros", executable="spawn_entity.py",
                 arguments=["-file", LaunchConfiguration("robot"), "-entity", "bot", "-x", "1.5"])
    broadcaster = Node(package="controller_manager", executable="spawner",
                       arguments=["joint_state_broadcaster", "--controller-manager", "/controller_manager"])
    arm = Node(package="controller_manager", executable="spawner", arguments=["arm_controller"])
    return LaunchDescription([
        DeclareLaunchArgument("gui", default_value="true"),
        DeclareLaunchArgument("robot"),
        Node(package="rviz2", executable="rviz2", condition=IfCondition(gui)),
        Node(package="my_tools", executable="watcher", condition=UnlessCondition(gui)),
        GroupAction([DeclareLaunchArgument("gui", default_value="x"),
                     Node(package="demo_nodes_py", executable="talker")]),
        spawn,
        RegisterEventHandler(OnProcessExit(target_action=spawn, on_exit=[broadcaster])),
        RegisterEventHandler(OnProcessExit(target_action=broadcaster,
                                           on_exit=[TimerAction(period=2.0, actions=[arm])])),
        ExecuteProcess(cmd=["ros2", "control", "load_controller", "--set-state", "active",
                            "gripper_controller"]),
    ])
"""

BOX = (
    '<robot name="bot"><link name="base"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>'
    "</visual></link></robot>"
)


def test_arguments_conditions_groups_and_event_handlers(tmp_path, caplog):
    path, ws = _package(tmp_path, RULES)
    robot = tmp_path / "bot.urdf"
    robot.write_text(BOX)
    with pytest.raises(
        WorkspaceError,
        match=r'demo\.launch\.py: RuntimeError: Required launch argument "robot" was not provided',
    ):
        read_launch_py(path, {}, ws)
    with caplog.at_level(logging.INFO, logger="omtp_drake"):
        launch = read_launch_py(path, {"robot": str(robot)}, ws)
    assert [(n.pkg, n.type, n.args) for n in launch.nodes] == [
        ("gazebo_ros", "spawn_model", f"-urdf -file {robot} -model bot -x 1.5")
    ]
    # The spawners run when spawn_entity.py has ended, the second after the first, the timer's too.
    assert launch.controllers == ["gripper_controller", "joint_state_broadcaster", "arm_controller"]
    assert [w.split(": ", 1)[1] for w in launch.warnings] == [
        "node demo_nodes_py/talker (/talker) is not run by the cell"  # the group's own gui: no watcher
    ]
    assert f"{path}:23: " in launch.warnings[0]  # the line of its Node(...)
    assert "node rviz2/rviz2: omtp-drake shows the cell in Meshcat" in caplog.text
    launch = read_launch_py(path, {"robot": str(robot), "gui": "false"}, ws)
    assert "node my_tools/watcher (/watcher) is not run by the cell" in launch.warnings[0]
    with pytest.raises(WorkspaceError, match=r"condition 'maybe' is not one of: true, 1, false, 0"):
        read_launch_py(path, {"robot": str(robot), "gui": "maybe"}, ws)


def test_a_moveit_config_launch_is_refused_in_one_line(tmp_path):
    path, ws = _package(
        tmp_path,
        """\
        from launch import LaunchDescription
        from moveit_configs_utils import MoveItConfigsBuilder


        def generate_launch_description():
            return LaunchDescription([])
        """,
    )
    with pytest.raises(WorkspaceError) as error:
        cell_of(launch="demo demo.launch.py", workspace=tmp_path / "src")
    assert str(error.value) == (
        f"{path}:2: imports moveit_configs_utils: a launch that builds a MoveIt 2 config is not supported "
        "(MoveIt 2 is not on PyPI; the cell plans itself, see docs/ros2.md)"
    )


def test_spawn_entity_of_a_topic_nobody_publishes_is_one_error(tmp_path):
    path, ws = _package(
        tmp_path,
        """\
        from launch import LaunchDescription
        from launch_ros.actions import Node


        def generate_launch_description():
            return LaunchDescription([
                Node(package="gazebo_ros", executable="spawn_entity.py",
                     arguments=["-topic", "robot_description", "-entity", "bot"]),
            ])
        """,
    )
    with pytest.raises(
        WorkspaceError,
        match=r"demo\.launch\.py:7: spawn_entity\.py -topic robot_description: "
        "no robot_state_publisher of the launch publishes /robot_description",
    ):
        read_launch_py(path, {}, ws)


@pytest.fixture(scope="module")
def reach_run(tmp_path_factory) -> tuple[str, dict, dict]:
    """slider_arm_moves' reach.launch.py (the tutorial's rsp_sim.launch.py included, and the
    workspace's ``reach`` node) under ``omtp-drake ros2 --realtime`` until ``reach`` finished, with
    a student's plain rclpy node (tests/ros2_scripts/joint_names_node.py) started beside it by
    the test: (the cell's output, what ``reach`` reported, what the student's node saw)."""
    tmp = tmp_path_factory.mktemp("reach")
    report, seen = tmp / "reached.json", tmp / "seen.json"
    cell_args = ["--launch", "slider_arm_moves reach.launch.py", "--workspace", str(TUTORIAL_SRC)]
    with hold_domain() as held:
        cell_args += ["--arg", f"report:={report}", "--realtime"]
        node = [str(SCRIPTS / "joint_names_node.py"), str(seen)]
        out = run_cell_until(cell_args, "[reach-1] finished", held, patience=120, node_args=node)
    return out, json.loads(report.read_text()), json.loads(seen.read_text())


@needs_ros2
def test_under_ros2_a_plain_rclpy_node_sees_the_robots_joint_states(reach_run):
    cell_out, _, seen = reach_run
    assert "reach.launch as node /omtp_cell" in cell_out and "stopped at t=" in cell_out
    assert seen["names"] == ["slider_joint", "arm_joint"]
    assert len(seen["positions"]) == 2 and all(abs(q) < 10.0 for q in seen["positions"])


@needs_ros2
def test_the_launch_starts_the_workspaces_own_rclpy_node_beside_the_cell(tmp_path, domain):
    """slider_arm_moves' settings.launch.py (a student's ament_python package: its node is a
    console script of setup.py) starts ``settings`` with a name, a namespace, parameters and a
    remapping: rclpy in the node reads them as ros2 launch gives them, and the node, still
    spinning when the run ends, is stopped with Ctrl-C and ends cleanly."""
    report = tmp_path / "settings.json"
    cell_args = ["--launch", "slider_arm_moves settings.launch.py", "--workspace", str(TUTORIAL_SRC)]
    # Paced (--realtime): the node starts in wall time; the cell need not run flat out meanwhile.
    cell_args += ["--arg", f"report:={report}", "--realtime"]
    out = run_cell_until(cell_args, "settings written", domain, patience=240)
    assert "[settings-1] started" in out, out[-3000:]
    assert "[settings-1] finished cleanly" in out, out[-3000:]
    assert json.loads(report.read_text()) == {
        "name": "arm_settings",
        "namespace": "/cell",
        "slider": 0.8,
        "arm": 0.6,
        "topic": "/set_joint_trajectory",
    }


@needs_ros2
def test_the_launched_node_and_the_cell_exchange_messages(reach_run):
    """slider_arm_moves' reach.launch.py includes the tutorial's launch and starts ``reach``
    (parameters, a remapping) the moment the cell is up: the node's trajectory reaches the cell
    and the cell's /joint_states reach the node, which reports the pose it saw and ends by itself.
    (It once never matched the cell's topics in 3 of about 17 runs: a Fast DDS peer's type lookup
    answered by the cell's Cyclone participant; omtp_drake.ros2.network.cell_participant_profile.)"""
    out, seen, _ = reach_run
    assert "[reach-1] finished cleanly" in out, out[-3000:]
    assert "Inconsistent TypeObject" not in out, out[-3000:]
    # No parts, no spawner: nothing Gazebo's model services would act on, so no line about them.
    assert "not served on ROS 2" not in out, out[-3000:]
    assert seen["names"] == ["slider_joint", "arm_joint"]
    assert seen["positions"] == pytest.approx([0.8, 0.6], abs=0.01)


def test_the_workspaces_ros2_node_is_one_warning_where_it_does_not_run(caplog):
    cell = cell_of(launch="slider_arm_moves reach.launch.py", workspace=TUTORIAL_SRC, with_nodes=True)
    assert [n.program.entry for n in cell.nodes if n.program] == ["slider_arm_moves.reach:main"]
    assert cell.ros2_only == [
        f"{TUTORIAL_SRC}/slider_arm_moves/launch/reach.launch.py:19: "
        "ROS 2 node slider_arm_moves/reach (/reach) runs under omtp-drake ros2 only"
    ]
    node = cell.nodes[0]
    assert node.argv == (
        "--ros-args", "-r", "__node:=reach", "-r", "joint_trajectory:=/set_joint_trajectory",
        "-p", "slider:=0.8", "-p", "arm:=0.6", "-p", 'report:="/tmp/reached.json"',
    )  # fmt: skip


def test_view_launch_shows_the_robot_description_it_publishes(tmp_path):
    """``view --launch``: the URDF robot_state_publisher publishes on /robot_description."""
    from omtp_drake.cli import main

    out = tmp_path / "view.json"
    args = ["view", "--launch", LAUNCH, "--workspace", str(TUTORIAL_SRC), "--json", str(out)]
    assert main(args) == 0
    listed = json.loads(out.read_text())
    assert [j["name"] for j in listed["joints"] if j["type"] != "fixed"] == ["slider_joint", "arm_joint"]
    assert {"base_link", "slider_link", "arm_link", "camera_link"} <= set(listed["links"])


def test_a_namespaced_state_publisher_with_a_yaml_file_feeds_its_spawn(tmp_path):
    params = tmp_path / "rsp.yaml"
    params.write_text(f"robot_state_publisher:\n  ros__parameters:\n    robot_description: '{BOX}'\n")
    path, ws = _package(
        tmp_path,
        f"""\
        from launch import LaunchDescription
        from launch.actions import GroupAction
        from launch_ros.actions import Node, PushRosNamespace


        def generate_launch_description():
            return LaunchDescription([GroupAction([
                PushRosNamespace("arm2"),
                Node(package="robot_state_publisher", executable="robot_state_publisher",
                     parameters=["{params}"]),
                Node(package="gazebo_ros", executable="spawn_entity.py",
                     arguments=["-topic", "robot_description", "-entity", "arm2", "-y", "1"]),
            ])])
        """,
    )
    launch = read_launch_py(path, {}, ws)
    assert launch.params["arm2"]["robot_description"] == BOX
    assert [(n.name, n.args) for n in launch.nodes] == [
        ("/arm2/spawn_entity", "-urdf -param /arm2/robot_description -model arm2 -y 1")
    ]
