"""``omtp-drake ros2 --launch 'PKG FILE.launch.py [ARG:=VALUE ...]'``: a ROS 2 launch file
as ``ros2 launch`` runs it, with the in-house ``launch``/``launch_ros`` API (neither is on
PyPI): the URDF tutorial's rsp_sim.launch.py (tests/fixtures/tutorial_ws, written here in
its form) brings the robot up in Gazebo's empty world, or in ``world:=FILE``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from test_ros2 import PATIENCE, _loopback_env, domain, needs_ros2

from omtp_drake.errors import ConfigError, NotSupportedError
from omtp_drake.ros2.launch_py import load_launch, plan_scenario

__all__ = ["domain"]  # the fixture, used by name

WS = Path(__file__).parent / "fixtures" / "tutorial_ws"
WORLD = WS / "src" / "slider_arm_description" / "worlds" / "obstacles.world"
RSP_SIM = "slider_arm_description rsp_sim.launch.py"


def test_rsp_sim_spawns_the_robot_from_robot_description_in_the_empty_world(tmp_path):
    plan = load_launch(RSP_SIM, [WS])
    assert plan.gazebo and plan.world is None and plan.warnings == []
    assert plan.entity == "slider_arm" and plan.spawn_source == "topic:robot_description"
    assert '<robot name="slider_arm"' in plan.robot_description
    scenario = plan_scenario(plan, [WS], tmp_path)
    assert scenario.name == "empty_world" and [m.name for m in scenario.models] == ["slider_arm"]


def test_world_argument_reaches_gazebos_launch(tmp_path):
    """``world:=`` given to the top launch file is seen by the included gazebo.launch.py."""
    plan = load_launch(f"{RSP_SIM} world:={WORLD}", [WS])
    assert plan.world == str(WORLD)
    scenario = plan_scenario(plan, [WS], tmp_path)
    assert scenario.name == "obstacles" and [m.name for m in scenario.models] == ["slider_arm"]


LAUNCH = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, RegisterEventHandler, TimerAction
from launch.event_handlers import OnProcessExit
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    spawn = Node(package='gazebo_ros', executable='spawn_entity.py',
                 arguments=['-file', LaunchConfiguration('model'), '-entity', 'bot',
                            '-x', '1.5', '-Y', '0.5'])
    return LaunchDescription([
        DeclareLaunchArgument('model', description='the robot file'),
        DeclareLaunchArgument('mode', default_value='sim', choices=['sim', 'real']),
        Node(package='teleop_twist_keyboard', executable='teleop_twist_keyboard'),
        ExecuteProcess(cmd=['ros2', 'bag', 'record', '-a']),
        TimerAction(period=3.0, actions=[spawn]),
        RegisterEventHandler(OnProcessExit(target_action=spawn, on_exit=[
            Node(package='controller_manager', executable='spawner', arguments=['arm_controller'])])),
    ])
"""


@pytest.fixture
def package(tmp_path):
    root = tmp_path / "src" / "my_bot"
    (root / "launch").mkdir(parents=True)
    (root / "package.xml").write_text("<package format='3'><name>my_bot</name></package>")
    (root / "launch" / "bot.launch.py").write_text(LAUNCH)
    return tmp_path


def test_arguments_timers_handlers_and_unknown_nodes(package):
    model = WS / "src" / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
    plan = load_launch(f"my_bot bot.launch.py model:={model}", [package, WS])
    assert (plan.entity, plan.spawn_source, plan.xyz, plan.rpy) == (
        "bot",
        str(model),
        (1.5, 0, 0),
        (0, 0, 0.5),
    )
    assert len(plan.warnings) == 3 and all(" is not run here" in w for w in plan.warnings), plan.warnings
    assert "teleop_twist_keyboard/teleop_twist_keyboard" in plan.warnings[0]
    assert "controller_manager/spawner" in plan.warnings[2]
    with pytest.raises(ConfigError, match="'model' has no value: give model:=VALUE"):
        load_launch("my_bot bot.launch.py", [package])
    with pytest.raises(ConfigError, match="mode:='fake' is not one of sim, real"):
        load_launch(f"my_bot bot.launch.py model:={model} mode:=fake", [package])


def test_a_moveit_2_launch_is_refused_in_one_line(package):
    (package / "src" / "my_bot" / "launch" / "moveit.launch.py").write_text(
        "from moveit_configs_utils import MoveItConfigsBuilder\n\n"
        "def generate_launch_description():\n    return None\n"
    )
    with pytest.raises(NotSupportedError, match="MoveIt 2 is not on PyPI"):
        load_launch("my_bot moveit.launch.py", [package])
    assert "moveit_configs_utils" not in sys.modules and "launch" not in sys.modules


@needs_ros2
def test_the_command_brings_the_robot_up(tmp_path, domain):
    """The cell runs the launch's robot: its links go out on /tf_static and /tf (bagged here)."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    bag = tmp_path / "run.mcap"
    done = subprocess.run(
        [sys.executable, "-m", "omtp_drake.cli", "ros2", "--launch", RSP_SIM, "--workspace", str(WS)]
        + ["--timeout", "0.2", "--domain-id", str(domain), "--bag", str(bag)],
        env=_loopback_env(domain),
        capture_output=True,
        text=True,
        timeout=PATIENCE,
        start_new_session=True,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "empty_world as node /omtp_cell" in done.stdout and "stopped at t=0.20 s" in done.stdout
    with bag.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        static = next(m for _, _, _, m in reader.iter_decoded_messages(topics=["/tf_static"]))
        moving = next(m for _, _, _, m in reader.iter_decoded_messages(topics=["/tf"]))
    assert {"camera_link", "camera_link_optical"} <= {t.child_frame_id for t in static.transforms}
    assert {"slider_link", "arm_link"} <= {t.child_frame_id for t in moving.transforms}
