"""roslaunch's rules as the loader reads a student's launch files, worlds and plugins, and
one error line (file, line where known, the value) for each kind of bad input."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from omtp_drake.errors import MissingPackageError, WorkspaceError
from omtp_drake.launch import own_cell, student_workspace
from omtp_drake.launch.roslaunch import get_param, parse_launch_spec, read_launch

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


def _launch(tmp_path: Path, body: str, name: str = "test.launch") -> Path:
    path = tmp_path / name
    path.write_text(f'<?xml version="1.0"?>\n<launch>\n{body}\n</launch>\n')
    return path


def _read(tmp_path, body, args=None, environ=None):
    workspace = student_workspace([], environ={})
    return read_launch(_launch(tmp_path, body), args or {}, workspace, environ or {})


def test_args_defaults_values_if_unless_groups_remaps_and_params(tmp_path):
    (tmp_path / "cfg.yaml").write_text("spawner:\n  spawn_period: 3.0\n")
    launch = _read(
        tmp_path,
        """
  <arg name="robot" default="robot1"/>
  <arg name="fast" default="false"/>
  <arg name="period" value="$(eval 2 * 1.5)"/>
  <arg name="here" value="$(dirname)"/>
  <group ns="$(arg robot)">
    <param name="rate" value="$(arg period)"/>
    <node name="spawner" pkg="p" type="t" args="-x 1 -model $(arg robot)">
      <rosparam command="load" file="$(arg here)/cfg.yaml"/>
      <param name="~private" type="int" value="7"/>
      <remap from="/start_spawn" to="/spawn_object_once"/>
    </node>
  </group>
  <node if="$(arg fast)" name="skipped" pkg="p" type="t"/>
  <node unless="$(arg fast)" name="$(optenv NODE_NAME kept)" pkg="p" type="t"/>
""",
        args={"robot": "robot2"},
    )
    names = [n.name for n in launch.nodes]
    assert names == ["/robot2/spawner", "/kept"]
    spawner = launch.nodes[0]
    assert spawner.args == "-x 1 -model robot2" and spawner.namespace == "/robot2"
    assert spawner.remaps == {"/start_spawn": "/spawn_object_once"}
    assert get_param(launch.params, "/robot2/rate") == 3.0
    assert get_param(launch.params, "/robot2/spawner/spawner/spawn_period") == 3.0
    assert get_param(launch.params, "/robot2/spawner/private") == 7


def test_include_passes_only_the_args_given(tmp_path):
    _launch(
        tmp_path, '<arg name="world" default="empty"/><param name="w" value="$(arg world)"/>', "inner.launch"
    )
    launch = _read(
        tmp_path,
        '<include file="$(dirname)/inner.launch" ns="sim"><arg name="world" value="factory"/></include>',
    )
    assert get_param(launch.params, "/sim/w") == "factory"


@pytest.mark.parametrize(
    ("body", "args", "expected"),
    [
        (
            '<arg name="world"/>\n<param name="w" value="$(arg world)"/>',
            {},
            "test.launch:4: $(arg world) has no value",
        ),
        ('<arg name="world" value="a"/>', {"world": "b"}, "arg 'world' has a fixed value"),
        ('<arg name="world" default="a"/>', {"wrold": "b"}, "unused args [wrold]"),
        ('<include file="$(dirname)/nowhere.launch"/>', {}, "test.launch:3: <include file="),
        ('<node if="maybe" name="n" pkg="p" type="t"/>', {}, "if='maybe' is 'maybe', not a boolean"),
        ('<param name="x" value="$(env OMTP_NOT_SET)"/>', {}, "environment variable OMTP_NOT_SET is not set"),
        ('<param name="x" value="$(rospack x)"/>', {}, "unknown substitution $(rospack x)"),
        (
            '<param name="x" command="rosrun pkg make_urdf"/>',
            {},
            "param command 'rosrun pkg make_urdf' is not supported",
        ),
        ('<node name="n" pkg="p" type="t"', {}, "test.launch:4: not well-formed XML"),
    ],
)
def test_bad_launch_files_are_one_error_with_file_and_line(tmp_path, body, args, expected):
    with pytest.raises(WorkspaceError) as e:
        _read(tmp_path, body, args)
    assert expected in str(e.value)
    assert str(tmp_path) in str(e.value)
    assert "\n" not in str(e.value)


def test_a_missing_package_names_it_the_file_and_the_flag(tmp_path):
    with pytest.raises(MissingPackageError) as e:
        _read(tmp_path, '<include file="$(find omtp_gazebo)/launch/x.launch"/>')
    assert "omtp_gazebo" in str(e.value) and "test.launch:3" in str(e.value) and "--workspace" in str(e.value)


def test_the_launch_spec_is_roslaunchs_words():
    assert parse_launch_spec("omtp_lecture6 a1.launch paused:=false") == (
        "omtp_lecture6",
        "a1.launch",
        {"paused": "false"},
    )
    assert parse_launch_spec("/x/y.launch") == ("", "/x/y.launch", {})
    with pytest.raises(WorkspaceError, match="give 'PKG FILE.launch"):
        parse_launch_spec("a b c")


@pytest.fixture
def workspace(tmp_path):
    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "catkin_ws" / "src", src)
    return src


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


@pytest.mark.parametrize(
    ("file", "old", "new", "expected"),
    [
        (
            "omtp_gazebo/models/logical_camera1/model.sdf",
            "<near>0.2</near>",
            "<near>-0.2</near>",
            "logical_camera1/model.sdf:4: logical camera 'logical_camera_1': near=-0.2 is invalid",
        ),
        (
            "omtp_gazebo/models/conveyor/model.sdf",
            "<power>0</power>",
            "<power>150</power>",
            "conveyor/model.sdf:32: ROSConveyorBeltPlugin conveyor.power must be in [0, 100], got 150.0",
        ),
        (
            "omtp_support/urdf/break_beam/break_beam.gazebo.xacro",
            "<max>0.6</max>",
            "<max>2.0</max>",
            "break beam max_range 2 is not supported",
        ),
        (
            "omtp_gazebo/models/logical_camera1/model.sdf",
            "<robotNamespace>omtp</robotNamespace>",
            "<robotNamespace>my factory</robotNamespace>",
            "(ros_logical_camera_1) <robotNamespace>: namespace 'my factory' is not valid",
        ),
        (
            "omtp_support/urdf/bin/bin.xacro",
            '<xacro:bin_urdf prefix="$(arg prefix)"/>',
            '<xacro:bin_urdff prefix="$(arg prefix)"/>',
            "bin.xacro: xacro error",
        ),
        (
            "omtp_support/urdf/robot_system/robot_system.xacro",
            '<xacro:arg name="robot_type" default="ur10"/>',
            '<xacro:arg name="robot_type" default="ur10"/>\n  <link name="$(arg no_such_arg)"/>',
            "robot_system.xacro: $(arg no_such_arg) has no value",
        ),
        (
            "omtp_gazebo/models/deletion_wall/model.sdf",
            '<collision name="collision">',
            '<collision name="collision"><pose>0 0 0 0 0</pose>',
            "deletion_wall/model.sdf: Drake's SDF parser refuses it",
        ),
        (
            "omtp_gazebo/worlds/lecture6_assignment1.world",
            "<pose>1.2 1.8 2.0 0 1.5708 0</pose>",
            "<pose>1.2 1.8 2.0 0 1.5708</pose>",
            "lecture6_assignment1.world:32: <pose> needs 6 numbers",
        ),
        (
            "omtp_gazebo/launch/spawn_robots.launch",
            "-x 0.5 -y 1.8 -z 0.95",
            "-x 0.5 -y 1.8 -z 0.95 -R 0.3",
            "arm robot1 is tilted",
        ),
    ],
)
def test_bad_files_in_a_workspace_are_one_error_naming_the_file_and_value(
    workspace, file, old, new, expected
):
    _edit(workspace / file, old, new)
    with pytest.raises(WorkspaceError) as e:
        own_cell(LAUNCH, workspace=[workspace], environ={})
    assert expected in str(e.value)
    assert "\n" not in str(e.value)


def test_a_package_nobody_provides_is_named_with_who_needs_it(workspace):
    shutil.rmtree(workspace / "omtp_utilities")
    shutil.rmtree(workspace / "omtp_support")
    with pytest.raises(MissingPackageError) as e:
        own_cell(LAUNCH, workspace=[workspace], environ={})
    assert "package 'omtp_support' not found" in str(e.value)
    assert "lecture6_assignment1.launch:" in str(e.value) and "--workspace DIR" in str(e.value)


def test_unknown_nodes_and_plugins_are_warning_lines_not_dropped(workspace):
    _edit(
        workspace / "omtp_lecture6/launch/lecture6_assignment1.launch",
        "</launch>",
        '  <node name="my_detector" pkg="my_pkg" type="detect.py"/>\n</launch>',
    )
    _edit(
        workspace / "omtp_gazebo/models/deletion_wall/model.sdf",
        "  </model>",
        '    <plugin name="light" filename="libMyLightPlugin.so"/>\n  </model>',
    )
    cell = own_cell(LAUNCH, workspace=[workspace], environ={})
    lines = "\n".join(cell.warnings)
    assert "node my_pkg/detect.py (/my_detector) is not run by the cell" in lines
    assert "Gazebo plugin libMyLightPlugin.so (light): not in the cell; ignored" in lines
    assert cell.scenario.deletion_wall


def test_a_students_own_moveit_config_is_the_runs(workspace):
    config = workspace / "omtp_moveit_config"
    (config / "config").mkdir(parents=True)
    (config / "launch").mkdir()
    (config / "package.xml").write_text("<package format='2'><name>omtp_moveit_config</name></package>")
    (config / "config" / "omtp.srdf").write_text("<robot name='omtp'/>")
    (config / "launch" / "move_group.launch").write_text(
        "<launch><include file='$(find nowhere)/x'/></launch>"
    )
    cell = own_cell(LAUNCH, workspace=[workspace], environ={})
    assert cell.moveit_config == config


def test_a_world_alone_gives_its_cameras_belt_and_wall(workspace):
    _edit(
        workspace / "omtp_gazebo/models/logical_camera2/model.sdf",
        "<!-- Noise, off as in the lecture:",
        "<position_noise><noise><type>gaussian</type><mean>0</mean><stddev>0.002</stddev></noise>"
        "</position_noise>\n      <!--",
    )
    cell = own_cell(world=workspace / "omtp_gazebo/worlds/lecture6_assignment1.world", workspace=[workspace])
    cameras = {c.name: c for c in cell.scenario.cameras}
    assert cameras["logical_camera_2"].position_noise_sigma == 0.002
    assert cameras["logical_camera_1"].xyz == [1.2, 1.8, 2.0]
    assert cell.scenario.conveyor is not None and cell.scenario.deletion_wall and not cell.scenario.robots


def test_an_unknown_plugin_in_a_spawned_urdf_is_a_warning_line(workspace):
    _edit(
        workspace / "omtp_support/urdf/bin/bin.gazebo.xacro",
        "<static>true</static>",
        '<static>true</static>\n      <plugin name="weigher" filename="libBinScalePlugin.so"/>',
    )
    cell = own_cell(LAUNCH, workspace=[workspace], environ={})
    assert any("Gazebo plugin libBinScalePlugin.so (weigher): not in the cell" in w for w in cell.warnings)


def test_lecture7s_pick_demo_and_a_students_spawn_point(workspace):
    """omtp_pick_demo.launch: the spawner of conveyor_object.yaml behind /start_spawn and the
    break beam stopping the belt; lecture 7's edit of the spawn point moves the spawner."""
    cell = own_cell("omtp_gazebo omtp_pick_demo.launch", workspace=[workspace], environ={})
    spawner = cell.scenario.spawner
    assert (spawner.xyz, spawner.period, spawner.start_service) == ([1.2, 2.5, 1.021], 3.0, "/start_spawn")
    assert not spawner.stop_node and not spawner.one_at_a_time
    assert cell.scenario.conveyor.stop_on_beam and cell.scenario.break_beam
    _edit(workspace / "omtp_gazebo/config/conveyor_object.yaml", "[1.2, 2.5, 1.0]", "[1.3, 3.5, 1.0]")
    moved = own_cell("omtp_gazebo omtp_pick_demo.launch", workspace=[workspace], environ={})
    assert moved.scenario.spawner.xyz == [1.3, 3.5, 1.021]
