"""A student's world and launch load as Gazebo loads them: every model of its own (a table,
a cube, a URDF box spawned on a shelf) is in the cell with its own geometry, pose and
statics, and tf knows it by name; what sdformat and roslaunch only warn about is one warning
line naming file:line, and the rest loads. Fixtures: ``tests/fixtures/world_ws`` (written here)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.cli import main
from omtp_drake.errors import ConfigError, MissingPackageError, WorkspaceError
from omtp_drake.launch import own_cell
from omtp_drake.viz.browser import find_browser

FIXTURES = Path(__file__).resolve().parent / "fixtures"
WORLD_WS = FIXTURES / "world_ws" / "src"
TABLE_CUBE = WORLD_WS / "my_cell" / "worlds" / "table_cube.world"
COURSE_WS = FIXTURES / "catkin_ws" / "src"
COURSE_LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
#: The table's top (m) and the cube's half edge.
TABLE_TOP, CUBE_HALF = 0.75, 0.05


def _tf(capsys, *argv: str) -> np.ndarray:
    assert main(["tf-echo", *argv, "--json"]) == 0, capsys.readouterr().err
    return np.array(json.loads(capsys.readouterr().out)["translation"])


def test_a_world_of_its_own_models_is_loaded_as_gazebo_places_them():
    # (its package's models are found without --workspace, as in a sourced workspace)
    cell = own_cell(world=TABLE_CUBE, environ={})
    models = {m.name: m for m in cell.scenario.models}
    assert sorted(models) == ["cube", "table"]
    assert models["table"].static and not models["cube"].static
    assert models["table"].xyz == [-3.0, 3.0, 0.0] and models["cube"].xyz == [-3.0, 3.0, 1.2]
    assert cell.scenario.gravity == [0.0, 0.0, -9.81]
    assert not any("not added" in w for w in cell.warnings)
    # The world's physics step: said once, the cell keeps its own.
    assert sum("max_step_size 0.001 s" in w for w in cell.warnings) == 1


def test_the_free_cube_lands_on_the_static_table(capsys):
    argv = ["--world", str(TABLE_CUBE), "--workspace", str(WORLD_WS)]
    start = _tf(capsys, *argv, "--time", "0", "world", "cube")
    assert start == pytest.approx([-3.0, 3.0, 1.2], abs=1e-6)
    landed = _tf(capsys, *argv, "--time", "2", "world", "cube")
    assert landed == pytest.approx([-3.0, 3.0, TABLE_TOP + CUBE_HALF], abs=0.01)
    table = _tf(capsys, *argv, "--time", "2", "world", "table")
    assert table == pytest.approx([-3.0, 3.0, 0.0], abs=1e-9)


def test_a_launch_spawns_a_non_course_urdf_box_onto_its_shelf(capsys):
    argv = ["--launch", "my_cell shelf.launch", "--workspace", str(WORLD_WS)]
    cell = own_cell("my_cell shelf.launch", workspace=[WORLD_WS], environ={})
    assert sorted(m.name for m in cell.scenario.models) == ["box", "cube", "shelf", "table"]
    board = _tf(capsys, *argv, "--time", "0", "world", "shelf_board")
    assert board == pytest.approx([-5.0, 3.0, 0.6], abs=1e-9)
    box = _tf(capsys, *argv, "--time", "1.5", "world", "box_link")
    # On the board (0.6 + 0.02), not in it nor through it.
    assert box == pytest.approx([-5.0, 3.0, 0.62 + 0.05], abs=0.01)


@pytest.fixture
def course_ws(tmp_path):
    src = tmp_path / "src"
    shutil.copytree(COURSE_WS, src)
    return src


def _insert_after(path: Path, anchor: str, lines: str) -> int:
    """Inserts ``lines`` after the line holding ``anchor``; returns the first new line's number."""
    text = path.read_text().splitlines(keepends=True)
    (index,) = [i for i, line in enumerate(text) if anchor in line]
    text.insert(index + 1, lines)
    path.write_text("".join(text))
    return index + 2


def test_a_stray_xacro_call_and_urdf_joint_in_a_world_are_one_warning_each(course_ws):
    world = course_ws / "omtp_gazebo" / "worlds" / "lecture6_assignment1.world"
    first = _insert_after(
        world,
        "<world name=",
        '    <xacro:logical_camera_macro name="logical_camera_3" parent="world"/>\n'
        '    <joint name="camera3_joint" type="fixed">\n'
        '      <parent link="world"/>\n      <child link="logical_camera_3_link"/>\n    </joint>\n',
    )
    cell = own_cell(COURSE_LAUNCH, workspace=[course_ws], environ={})
    strays = [w for w in cell.warnings if "under <world>" in w]
    assert strays == [
        f"{world}:{first}: XML element <xacro:logical_camera_macro> under <world> is not defined in SDF "
        "(a xacro call?); ignored",
        f"{world}:{first + 1}: XML element <joint> (name 'camera3_joint') under <world> is not an SDF "
        "world's joint (a URDF joint?); ignored, as Gazebo does",
    ]
    built_in = own_cell(COURSE_LAUNCH, workspace=[COURSE_WS], environ={})
    assert cell.scenario.cameras == built_in.scenario.cameras
    # (no model of their own: the cameras' housings, the bin's and pedestals' model entries are the
    # launch's, as in the course)
    own = ["logical_camera_1_own", "logical_camera_2_own", "bin_1_", "robot1_pedestal", "robot2_pedestal"]
    assert [m.name for m in cell.scenario.models] == [m.name for m in built_in.scenario.models] == own


def test_an_unknown_launch_tag_is_a_warning_as_roslaunch_gives(course_ws):
    launch = course_ws / "omtp_lecture6" / "launch" / "lecture6_assignment1.launch"
    line = _insert_after(launch, "<launch>", '  <rosparm command="load" file="nowhere.yaml"/>\n')
    cell = own_cell(COURSE_LAUNCH, workspace=[course_ws], environ={})
    assert [w for w in cell.warnings if "unrecognized" in w] == [
        f"{launch}:{line}: unrecognized tag <rosparm>; ignored (launch tags: arg, include, group, remap, "
        "param, rosparam, node, env, machine, test)"
    ]


def test_a_model_from_gazebos_online_database_is_one_error_naming_the_uri_and_folders(tmp_path):
    world = tmp_path / "tutorial.world"
    world.write_text(
        '<?xml version="1.0"?>\n<sdf version="1.6">\n  <world name="default">\n'
        "    <include><uri>model://ground_plane</uri></include>\n"
        "    <include><uri>model://jersey_barrier</uri><pose>2 0 0 0 0 0</pose></include>\n"
        "  </world>\n</sdf>\n"
    )
    with pytest.raises(MissingPackageError) as e:
        own_cell(world=world, workspace=[WORLD_WS], environ={})
    message = str(e.value)
    assert f"{world}:5: Gazebo model 'jersey_barrier' not found" in message
    assert "searched:" in message and str(WORLD_WS) in message
    assert "online model database (http://models.gazebosim.org)" in message
    assert "\n" not in message


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        (
            "<pose>-3 3 1.2 0 0 0.3</pose>",
            "<pose>-3 3 nan 0 0 0.3</pose>",
            "table_cube.world:22: <pose> '-3 3 nan",
        ),
        ("<pose>-3 3 1.2 0 0 0.3</pose>", "<pose>-3 3 1.2 0 0</pose>", "table_cube.world:22: <pose> needs 6"),
        ("<gravity>0 0 -9.81</gravity>", "<gravity>0 0</gravity>", "table_cube.world:4: <gravity> needs 3"),
        ("<max_step_size>0.001<", "<max_step_size>-1<", "table_cube.world:5: <max_step_size> '-1' must be"),
        ('<model name="cube">', '<model name="cube"', "table_cube.world:23: not well-formed XML"),
        (
            "<mass>0.5</mass>",
            "<mass>-0.5</mass>",
            "table_cube.world:22: link 'link': inertial mass '-0.5' must be 1 finite number > 0",
        ),
        ("<pose>-3 3 1.2 0 0 0.3</pose>", '<pose relative_to="tabel">0 0 1.2 0 0 0</pose>', "no such model"),
    ],
)
def test_bad_world_values_are_one_error_naming_file_line_and_value(tmp_path, old, new, expected):
    world = tmp_path / "table_cube.world"
    text = TABLE_CUBE.read_text()
    assert old in text
    world.write_text(text.replace(old, new))
    with pytest.raises((WorkspaceError, ConfigError)) as e:
        cell = own_cell(world=world, workspace=[WORLD_WS], environ={})
        from omtp_drake.sim.runtime import FactoryRuntime

        FactoryRuntime(cell.scenario)
    assert expected in str(e.value)
    assert "\n" not in str(e.value)


def test_a_pose_relative_to_a_model_of_the_world(tmp_path):
    world = tmp_path / "relative.world"
    text = TABLE_CUBE.read_text().replace('<sdf version="1.6">', '<sdf version="1.7">')
    world.write_text(
        text.replace("<pose>-3 3 1.2 0 0 0.3</pose>", '<pose relative_to="table">0 0 1.2 0 0 0</pose>')
    )
    cell = own_cell(world=world, workspace=[WORLD_WS], environ={})
    (cube,) = [m for m in cell.scenario.models if m.name == "cube"]
    assert cube.xyz == pytest.approx([-3.0, 3.0, 1.2])


def test_a_gazebo_sensor_on_a_link_that_does_not_exist_is_one_error(tmp_path):
    urdf = tmp_path / "box.urdf"
    text = (WORLD_WS / "my_cell" / "urdf" / "box.urdf").read_text()
    urdf.write_text(
        text.replace(
            "</robot>",
            '  <gazebo reference="camera_link">\n    <sensor name="cam" type="camera"/>\n'
            "  </gazebo>\n</robot>",
        )
    )
    with pytest.raises(ConfigError) as e:
        main_args = ["view", str(urdf), "--json"]
        from omtp_drake.scenario import model_from_file

        model_from_file(urdf)
    line = 1 + urdf.read_text()[: urdf.read_text().index('reference="camera_link"')].count("\n")
    assert str(e.value) == (
        f"{urdf}:{line}: <gazebo reference='camera_link'>: no link or joint of that name; "
        "valid links: box_link"
    )
    assert main(main_args) == 2


def test_a_gazebo_sensor_on_a_joint_is_one_error_where_the_xacro_writes_it(tmp_path, capsys):
    """The tutorial's depth camera moved from ``camera_link`` to ``camera_joint`` (a joint's
    ``<gazebo>`` holds joint sensors in Gazebo, which the cell has not): one line naming the
    included xacro and its line, the value and the valid links, before anything is built
    (it was a RuntimeError from the plant's GetBodyByName)."""
    ws = tmp_path / "src"
    shutil.copytree(FIXTURES / "tutorial_ws" / "src", ws)
    gazebo = ws / "slider_arm_description" / "urdf" / "slider_arm.gazebo.xacro"
    text = gazebo.read_text()
    sensor = text.index('<sensor type="depth"')
    at = text.rindex('reference="camera_link"', 0, sensor)
    gazebo.write_text(text[:at] + 'reference="camera_joint"' + text[at + len('reference="camera_link"') :])
    line = 1 + text[:at].count("\n")
    robot = ws / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
    assert main(["view", str(robot), "--workspace", str(ws), "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{gazebo}:{line}: <gazebo reference='camera_joint'>: is a joint" in err
    assert "valid links: world, base_link, slider_link, arm_link, camera_link, camera_link_optical" in err
    assert "\n" not in err and "GetBodyByName" not in err


def test_a_scenario_models_sensor_on_no_link_is_one_error():
    """A scenario document's typed model entry whose sensor names no link of its model: one
    error naming the file, the sensor, the value and the valid links (not GetBodyByName's)."""
    import dataclasses

    from omtp_drake.errors import UnknownNameError
    from omtp_drake.scenario import scenario_from_dict, with_robot

    robot = FIXTURES / "tutorial_ws" / "src" / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
    scenario = with_robot(None, robot, [FIXTURES / "tutorial_ws" / "src"])
    document = {"name": "mine", "models": [dataclasses.asdict(m) for m in scenario.models]}
    (sensor,) = [s for m in document["models"] for s in m["gazebo"]["sensors"]]
    sensor["link"] = "camera_joint"
    with pytest.raises(UnknownNameError) as e:
        scenario_from_dict(document, source="mine.yaml", name="mine")
    assert str(e.value) == (
        f"unknown link of {robot}'s sensor 'tip_camera' 'camera_joint'; valid: arm_link, base_link, "
        "camera_link, camera_link_optical, slider_link, world"
    )


def test_view_lists_every_model_of_a_world(capsys):
    assert main(["view", str(TABLE_CUBE), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert [m["name"] for m in info["models"]] == ["table", "cube"]
    assert info["models"][0]["links"] == ["top", "legs"]
    # The course's world too, every model as its file has it (the belt's links are in its
    # nested models).
    world = COURSE_WS / "omtp_gazebo" / "worlds" / "lecture6_assignment1.world"
    assert main(["view", str(world), "--json"]) == 0
    models = {m["name"]: m["links"] for m in json.loads(capsys.readouterr().out)["models"]}
    assert sorted(models) == ["conveyor_belt", "deletion_wall", "logical_camera_1", "logical_camera_2"]
    assert models["conveyor_belt"] == ["link", "belt"] and models["deletion_wall"] == ["sensing_link"]


@pytest.mark.skipif(find_browser() is None, reason="no chromium")
def test_view_of_a_world_shows_the_table_and_the_cube(tmp_path):
    png = tmp_path / "world.png"
    assert main(["view", str(TABLE_CUBE), "--screenshot", str(png)]) == 0
    from matplotlib.image import imread

    rgb = imread(png)[..., :3]
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    blue = (b > 0.5) & (r < 0.2) & (g < 0.35)  # the cube (diffuse 0.1 0.3 0.9)
    brown = (r > g + 0.08) & (g > b) & (r > 0.15)  # the table top (0.55 0.35 0.2)
    assert blue.sum() > 200 and brown.sum() > 2000
    # The cube is above the table top in the picture.
    assert np.nonzero(blue)[0].mean() < np.nonzero(brown)[0].mean()


def test_a_value_libsdformat_cannot_read_in_an_included_model_is_one_error(tmp_path):
    # Found by bench/bench_world_fuzz.py: Drake logs libsdformat's "Unable to set value"
    # and goes on with the default pose; Gazebo's sdformat refuses the model.
    src = tmp_path / "src"
    shutil.copytree(WORLD_WS, src)
    sdf = src / "my_cell" / "models" / "work_table" / "model.sdf"
    sdf.write_text(sdf.read_text().replace("<pose>0.55 0.35 0 0 0 0</pose>", "<pose>abc 0.35 0 0 0 0</pose>"))
    with pytest.raises(WorkspaceError) as e:
        own_cell(world=src / "my_cell" / "worlds" / "table_cube.world", workspace=[src], environ={})
    assert f"{sdf}: Drake's SDF parser refuses it" in str(e.value) and "model.sdf:18" in str(e.value)
    assert "\n" not in str(e.value)


def test_a_xacro_error_of_several_lines_is_one_line(tmp_path):
    # Found by bench/bench_world_fuzz.py: xacro's "name ... is not defined" runs on over
    # two lines.
    src = tmp_path / "src"
    shutil.copytree(WORLD_WS, src)
    xacro_file = src / "my_cell" / "urdf" / "shelf.urdf.xacro"
    xacro_file.write_text(xacro_file.read_text().replace('name="board_height"', 'name="board_height_typo"'))
    with pytest.raises(WorkspaceError) as e:
        own_cell("my_cell shelf.launch", workspace=[src], environ={})
    assert str(e.value) == (
        f"{xacro_file}: xacro error: name 'board_height' is not defined when evaluating expression "
        "'board_height'"
    )


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [  # found by bench/bench_world_fuzz.py: Drake's URDF parser takes these, Gazebo's refuse them
        (
            '<box size="0.1 0.1 0.1"/>',
            '<box size="abc 0.1 0.1"/>',
            "'box_link': box size 'abc 0.1 0.1' must",
        ),
        ('<box size="0.1 0.1 0.1"/>', '<box size="inf 0.1 0.1"/>', "box size 'inf 0.1 0.1' must be 3 finite"),
        ('ixx="0.0005"', 'ixx="-1"', "link 'box_link': inertia ixx '-1' must be 1 finite number >= 0"),
        ('<mass value="0.3"/>', '<mass value="nan"/>', "inertial mass 'nan' must be 1 finite number > 0"),
        ("<visual>", '<visual><origin xyz="0 nan 0"/>', "origin xyz '0 nan 0' must be 3 finite numbers"),
    ],
)
def test_a_spawned_urdfs_bad_numbers_are_one_error(tmp_path, old, new, expected):
    src = tmp_path / "src"
    shutil.copytree(WORLD_WS, src)
    urdf = src / "my_cell" / "urdf" / "box.urdf"
    text = urdf.read_text()
    assert old in text
    urdf.write_text(text.replace(old, new, 1))
    with pytest.raises(WorkspaceError) as e:
        own_cell("my_cell shelf.launch", workspace=[src], environ={})
    assert expected in str(e.value) and str(urdf) in str(e.value) and "\n" not in str(e.value)


def test_an_included_models_bad_sdf_version_is_one_error(tmp_path):
    # Found by bench/bench_world_fuzz.py: libsdformat's stoi of the version was a ValueError.
    src = tmp_path / "src"
    shutil.copytree(WORLD_WS, src)
    sdf = src / "my_cell" / "models" / "work_table" / "model.sdf"
    sdf.write_text(sdf.read_text().replace('<sdf version="1.6">', '<sdf version="abc">'))
    with pytest.raises(WorkspaceError) as e:
        own_cell(world=src / "my_cell" / "worlds" / "table_cube.world", workspace=[src], environ={})
    assert str(e.value) == f"{sdf}:2: <sdf version='abc'> is not an SDF version (e.g. 1.6)"


def test_nested_models_include_by_path_and_scoped_link_names(tmp_path, capsys):
    world = tmp_path / "nest.world"
    table = WORLD_WS / "my_cell" / "models" / "work_table"
    world.write_text(
        f"""<?xml version="1.0"?>
<sdf version="1.7">
  <world name="nest">
    <include><uri>{table}</uri><name>desk</name><pose>2 -3 0 0 0 0</pose></include>
    <model name="rack">
      <static>true</static>
      <pose>-2 -3 0 0 0 0</pose>
      <link name="link">
        <collision name="c"><geometry><box><size>0.5 0.5 0.1</size></box></geometry></collision>
      </link>
      <model name="shelf">
        <pose>0 0 0.5 0 0 0</pose>
        <link name="link">
          <collision name="c"><geometry><box><size>0.5 0.5 0.05</size></box></geometry></collision>
        </link>
      </model>
    </model>
    <model name="cube">
      <pose relative_to="rack">0 0 0.8 0 0 0</pose>
      <link name="link"><inertial><mass>0.2</mass></inertial>
        <collision name="c"><geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision></link>
    </model>
  </world>
</sdf>
"""
    )
    argv = ["--world", str(world), "--time", "1"]
    # A static model's nested model is static too (Gazebo holds the whole tree); two models'
    # links both called "link" are Gazebo's scoped names.
    assert _tf(capsys, *argv, "world", "rack::shelf::link") == pytest.approx([-2.0, -3.0, 0.5], abs=1e-9)
    assert _tf(capsys, *argv, "world", "cube") == pytest.approx([-2.0, -3.0, 0.5 + 0.025 + 0.05], abs=0.005)
    assert _tf(capsys, *argv, "world", "desk") == pytest.approx([2.0, -3.0, 0.0], abs=1e-9)


def test_elements_sdf_does_not_define_inside_models_are_one_warning_each(tmp_path):
    # sdformat warns "not defined in SDF" and loads the model without them; Drake's parser
    # refuses them, so the loader takes them out first, naming file:line.
    src = tmp_path / "src"
    shutil.copytree(WORLD_WS, src)
    world = src / "my_cell" / "worlds" / "table_cube.world"
    strays = '      <frobnicate/>\n      <xacro:box_macro size="0.1"/>\n'
    line = _insert_after(world, '<model name="cube">', strays)
    sdf = src / "my_cell" / "models" / "work_table" / "model.sdf"
    sdf_line = _insert_after(sdf, '<link name="top">', "      <material_typo>wood</material_typo>\n")
    cell = own_cell(world=world, workspace=[src], environ={})
    assert sorted(m.name for m in cell.scenario.models) == ["cube", "table"]
    strays = [w for w in cell.warnings if "not defined in SDF" in w]
    assert sorted(strays) == sorted(
        [
            f"{world}:{line}: XML element <frobnicate> under <model> is not defined in SDF; ignored",
            f"{world}:{line + 1}: XML element <xacro:box_macro> under <model> is not defined in SDF "
            "(a xacro call?); ignored",
            f"{sdf}:{sdf_line}: XML element <material_typo> under <link> is not defined in SDF; ignored",
        ]
    )
    assert not any("frobnicate" in m.description or "typo" in m.description for m in cell.scenario.models)
