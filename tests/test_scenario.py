"""Scenario files: loading, inheritance and clear errors."""

import pytest
import yaml

from omtp_drake.cell.station import build_station
from omtp_drake.control.motion import ArmPlanner
from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError
from omtp_drake.scenario import (
    Scenario,
    as_scenario,
    load_scenario,
    scenario_document,
    scenario_from_dict,
    scenario_names,
)


def test_factory_scenario_contents():
    s = load_scenario("omtp_factory")
    assert s.name == "omtp_factory"
    assert [(r.name, r.model) for r in s.robots] == [("robot1", "ur10"), ("robot2", "ur5")]
    assert [c.name for c in s.cameras] == ["logical_camera_1", "logical_camera_2"]
    assert s.conveyor.power == 0.0 and s.parts == []
    assert "omtp_factory" in scenario_names()


def test_unknown_scenario_name_lists_choices():
    with pytest.raises(UnknownNameError, match="valid: .*omtp_factory") as e:
        load_scenario("omtp_fctory")
    assert "omtp_fctory" in str(e.value)


def test_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match="does not exist"):
        load_scenario(tmp_path / "nope.yaml")


def test_unknown_key_names_valid_keys(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("base: omtp_factory\nrobot: []\n")
    words = r"bad.yaml: unknown key 'robot' \(did you mean 'robots'\?\); valid keys: .*robots"
    with pytest.raises(ScenarioError, match=words):
        load_scenario(path)


def test_unknown_nested_key(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("robots:\n  - name: robot1\n    modle: ur10\n")
    with pytest.raises(ScenarioError, match="modle"):
        load_scenario(path)


def test_bad_values(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("base: omtp_factory\nconveyor: {power: 150}\n")
    with pytest.raises(ConfigError, match="150"):
        load_scenario(path)
    path.write_text("robots:\n  - {name: robot1, model: ur3}\n")
    with pytest.raises(UnknownNameError, match="ur3.*valid: ur10, ur5"):
        load_scenario(path)
    path.write_text("cameras:\n  - {name: cam_1, near: 0.5, far: 0.4}\n")
    with pytest.raises(ConfigError, match="far"):
        load_scenario(path)


def test_user_world_from_path_inherits_base(tmp_path):
    path = tmp_path / "one_arm.yaml"
    path.write_text(
        "base: omtp_factory\n"
        "description: only robot 2\n"
        "robots: !replace\n"
        "  - {name: robot2, model: ur5, xy: [-7.8, -1.5], pedestal_height: 0.7, yaw: 1.57,\n"
        "     pose_prefix: R2, gripper: vacuum_gripper2}\n")
    s = load_scenario(str(path))
    assert s.name == "one_arm" and [r.name for r in s.robots] == ["robot2"]
    assert len(s.cameras) == 2
    station = build_station(s)
    assert list(station.arms) == ["robot2"]


def test_base_merges_named_lists_by_name(tmp_path):
    """fill_bin changes one joint limit of robot 2 and keeps everything else of the base."""
    s = load_scenario("fill_bin")
    base = load_scenario("lecture6_assignment4")
    assert [r.name for r in s.robots] == ["robot1", "robot2"]
    r2, b2 = s.robot("robot2"), base.robot("robot2")
    assert r2.joint_limit == pytest.approx(2 * 3.141592653589793) and b2.joint_limit < 3.2
    assert (r2.model, r2.xy, r2.yaw, r2.gripper) == (b2.model, b2.xy, b2.yaw, b2.gripper)
    # A camera added by name; the course's two come from the base.
    assert [c.name for c in base.cameras] == ["logical_camera_1", "logical_camera_2",
                                              "logical_camera_bin_1"]
    # A child's item of a known name merges key by key.
    path = tmp_path / "near.yaml"
    path.write_text("base: omtp_factory\ncameras:\n  - {name: logical_camera_2, far: 1.5}\n")
    cam = {c.name: c for c in load_scenario(path).cameras}["logical_camera_2"]
    assert cam.far == 1.5 and cam.horizontal_fov == pytest.approx(0.65)


def test_pose_in_drake_transform_form(tmp_path):
    s = load_scenario("lecture6_assignment4")
    cam = {c.name: c for c in s.cameras}["logical_camera_bin_1"]
    assert cam.xyz == pytest.approx([-8.0, -2.2, 1.7])
    assert cam.rpy == pytest.approx([0.0, 3.141592653589793 / 2, 0.0])
    path = tmp_path / "both.yaml"
    path.write_text("base: omtp_factory\nparts:\n  - {name: p1, xyz: [0, 0, 0.1],\n"
                    "     pose: {translation: [0, 0, 0.1]}}\n")
    with pytest.raises(ScenarioError, match=r"parts\[p1\] gives both pose and xyz"):
        load_scenario(path)


def test_misspelt_nested_key_names_file_key_closest_and_valid(tmp_path):
    """Issue 11: the bad key, the file, the valid keys and the closest one."""
    path = tmp_path / "cams.yaml"
    path.write_text("base: omtp_factory\ncameras:\n  - {name: logical_camera_2, hfov: 0.7}\n")
    with pytest.raises(ScenarioError) as e:
        load_scenario(path)
    message = str(e.value)
    assert message.startswith("cams.yaml: cameras[logical_camera_2]: unknown key 'hfov'")
    assert "did you mean 'horizontal_fov'" in message and "valid keys: name, parent" in message


@pytest.mark.parametrize("text, words", [
    ("task: {robot: robot9}\n", ["task.robot", "robot9", "robot1, robot2"]),
    ("task: {camera: cam}\n", ["task.camera", "'cam'", "logical_camera_1"]),
    ("task: {bin: bin_7}\n", ["bin", "bin_7", "bin_1"]),
    ("conveyor: {stop_on_beam: true}\nbreak_beam: false\n", ["stop_on_beam needs break_beam"]),
    ("robots:\n  - {name: robot2, gripper: ''}\ntask: {robot: robot2}\n", ["has no gripper"]),
])
def test_cross_references_are_checked_at_load(tmp_path, text, words):
    path = tmp_path / "bad.yaml"
    path.write_text("base: omtp_factory\n" + text)
    with pytest.raises((ConfigError, UnknownNameError)) as e:
        load_scenario(path)
    for word in words:
        assert word in str(e.value)


@pytest.mark.parametrize("name, words", [
    ("world", ["name 'world' is taken by the cell", "reserved names: world, floor"]),
    ("floor", ["name 'floor' is taken by the cell"]),
    ("robot2_pedestal", ["names must be unique", "repeated: robot2_pedestal"]),
    ("bin_1", ["names must be unique", "repeated: bin_1"]),
])
def test_a_part_may_not_take_a_name_of_the_cell(tmp_path, name, words):
    path = tmp_path / "named.yaml"
    path.write_text(f"base: omtp_factory\nparts:\n  - {{name: {name}, xyz: [1.2, 1.8, 1.1]}}\n")
    with pytest.raises(ConfigError) as e:
        load_scenario(path)
    for word in words:
        assert word in str(e.value)


def test_only_parts_may_take_a_pool_name(tmp_path):
    path = tmp_path / "gripper.yaml"
    path.write_text("base: fill_bin\nrobots:\n  - {name: robot2, gripper: object_1}\n")
    with pytest.raises(ConfigError, match="name 'object_1': names object_<k> are the part pool's"):
        load_scenario(path)


def test_inner_builders_take_a_scenario_and_say_how_to_load_one():
    """A name becomes a Scenario at the entry points (as_scenario); inside, a name is refused."""
    with pytest.raises(ConfigError, match=r"build_station takes a Scenario, got str 'omtp_factory'; load"):
        build_station("omtp_factory")
    with pytest.raises(ConfigError, match=r"ArmPlanner takes a Scenario, got str"):
        ArmPlanner("lecture6_assignment4", "robot2")
    scenario = load_scenario("omtp_factory")
    assert as_scenario(scenario) is scenario
    loaded = as_scenario("omtp_factory")
    assert isinstance(loaded, Scenario) and loaded.name == "omtp_factory"


def test_with_time_step_changes_only_the_step_and_refuses_a_bad_one():
    scenario = load_scenario("fill_bin")
    stepped = scenario.with_time_step(0.002)
    assert stepped.plant_config.time_step == 0.002
    assert scenario.plant_config.time_step != 0.002  # the original is untouched
    before, after = scenario.plant_config, stepped.plant_config
    assert after.discrete_contact_approximation == before.discrete_contact_approximation
    with pytest.raises(ConfigError, match=r"time_step must be in .*got 0.05"):
        scenario.with_time_step(0.05)


@pytest.mark.parametrize("text, message", [
    ("cameras:\n  - {name: c, occlusion: 'yes'}\n",
     "x.yaml: cameras[c].occlusion must be true or false, got 'yes'"),
    ("cameras:\n  - {name: c, xyz: [a, b, c]}\n",
     "x.yaml: cameras[c].xyz must be a list of numbers, got ['a', 'b', 'c']"),
    ("seed: 1.5\n", "x.yaml: seed must be an integer, got 1.5"),
    ("conveyor: 3\n",
     "x.yaml: conveyor must be a mapping of keys (power, stop_on_beam, xyz, yaw, roll, pitch, "
     "belt_size), got 3"),
    ("robots: [3]\n", "x.yaml: robots[0] must be a mapping of keys (name, model,"),
    ("parts:\n  - {name: p, pose: {translation: [1, 2]}}\n",
     "x.yaml: parts[p].pose.translation must be 3 numbers, got [1, 2]"),
    ("parts:\n  - {name: p, pose: {transl: [1, 2, 3]}}\n",
     "x.yaml: parts[p].pose: unknown key 'transl' (did you mean 'translation'?); "
     "valid keys: base_frame, translation, rotation"),
    ("parts:\n  - {name: p, pose: {translation: [1, 2, 3], rotation: !Rpy {deg: [1, 2]}}}\n",
     "x.yaml: parts[p].pose.rotation must be one of !Identity {}, !Rpy {deg}, !AngleAxis {angle_deg, axis}, "
     "!Uniform {}, got !Rpy {'deg': [1, 2]}"),
    ("parts:\n  - {name: p, pose: {translation: [1, 2, 3], rotation: !Uniform {}}}\n",
     "x.yaml: parts[p].pose must be a fixed pose; valid rotations: !Rpy"),
])
def test_a_refused_document_names_the_key_path_and_what_is_valid(text, message):
    """Drake's typed loader is the one checker; a refusal is said at the first refused key."""
    from omtp_drake.scenario.loader import _Loader

    with pytest.raises(ScenarioError) as e:
        scenario_from_dict(yaml.load(text, Loader=_Loader), source="x.yaml")
    assert str(e.value).startswith(message)
    assert "\n" not in str(e.value)


def test_values_are_typed_by_drakes_rules():
    """What Drake's loader converts (a quoted number, an int for a float) loads as that type."""
    scenario = scenario_from_dict({"seed": "7", "cameras": [{"name": "c", "far": 2}]})
    assert scenario.seed == 7 and isinstance(scenario.cameras[0].far, float)


def test_a_robot_name_given_as_a_list_is_one_error_naming_the_file_and_value(tmp_path):
    """Found by fuzzing: the ``base:`` merge looked items up by a list (TypeError)."""
    path = tmp_path / "listed_name.yaml"
    path.write_text("base: omtp_factory\nrobots:\n  - name: [robot1]\n    yaw: 0.1\n")
    with pytest.raises(ScenarioError) as e:
        load_scenario(path)
    assert str(path) in str(e.value) and "['robot1']" in str(e.value) and "must be a string" in str(e.value)


def test_extra_frames_hang_on_cell_frames_and_an_unknown_parent_is_refused():
    from omtp_drake.cell.frames import FrameTree

    doc = {"base": "", "frames": [{"name": "camera_mount", "parent": "robot1_tool0", "xyz": [0, 0, 0.1]}]}
    scenario = scenario_from_dict({**scenario_document("omtp_factory"), **doc})
    station = build_station(scenario)
    assert "camera_mount" in FrameTree(station.plant).names()
    bad = {**scenario_document("omtp_factory"), "frames": [{"name": "camera_mount", "parent": "nowhere"}]}
    with pytest.raises(ConfigError, match="parent 'nowhere' is no frame of the cell"):
        build_station(scenario_from_dict(bad))


def test_plant_steps_up_to_the_studied_20_ms_are_accepted():
    # bench/bench_plant_step.py: every task outcome is the same at 16 and 20 ms as at 10 ms.
    assert load_scenario("fill_bin").with_time_step(0.02).plant_config.time_step == 0.02
    with pytest.raises(ConfigError, match=r"must be in \[0\.0001, 0\.02\] s .*got 0\.025"):
        load_scenario("fill_bin").with_time_step(0.025)
