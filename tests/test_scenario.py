"""Scenario files: loading, inheritance and clear errors."""

import pytest

from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError
from omtp_drake.scenario import load_scenario, scenario_names
from omtp_drake.station import build_station


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
    with pytest.raises(ScenarioError, match=r"unknown key\(s\) robot; valid keys: .*robots"):
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
        "robots:\n"
        "  - {name: robot2, model: ur5, xy: [-7.8, -1.5], pedestal_height: 0.7, yaw: 1.57,\n"
        "     pose_prefix: R2, gripper: vacuum_gripper2}\n")
    s = load_scenario(str(path))
    assert s.name == "one_arm" and [r.name for r in s.robots] == ["robot2"]
    assert len(s.cameras) == 2
    station = build_station(s)
    assert list(station.arms) == ["robot2"]
