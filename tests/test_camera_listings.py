"""A student's logical camera plugin says which models it publishes and how it names them
(``known_model_types``, ``known_model_names``, ``anonymize_models``, ``model_frame_prefix``;
tests/fixtures/camera_listings laid over a copy of tests/fixtures/group_ws): read once into
the scenario's ``plugin_names.camera_listings``, applied by the plugin layer to what both
transports serve (the camera topics and tf's detected frames). Its ROS 2 test (the cameras'
rviz2 markers) is in tests/test_plugin_names.py, whose ROS 2 cell it shares."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from omtp_drake.errors import WorkspaceError
from omtp_drake.gazebo.logical_camera import PluginListing, model_id
from omtp_drake.launch import own_cell
from omtp_drake.launch.plugins import camera_listing, plugins_in
from omtp_drake.scenario.plugin_names import CameraListing

FIXTURES = Path(__file__).resolve().parent / "fixtures"
EDITS = FIXTURES / "camera_listings"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
OVERLAY = {
    "logical_camera1.sdf": "omtp_gazebo/models/logical_camera1/model.sdf",
    "logical_camera2.sdf": "omtp_gazebo/models/logical_camera2/model.sdf",
}


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    src = tmp_path_factory.mktemp("listings") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    for edit, target in OVERLAY.items():
        shutil.copyfile(EDITS / edit, src / target)
    return src


def test_their_rules_are_read_once_into_the_scenario(workspace):
    names = own_cell(LAUNCH, workspace=[workspace], environ={}).scenario.plugin_names
    assert names.camera_listings == {
        "logical_camera_1": CameraListing(
            known_model_types=["object", "workcell"], model_frame_prefix="belt_cam_"
        ),
        "logical_camera_2": CameraListing(
            known_model_types=["bin_1"], known_model_names=["conveyor_belt"], anonymize_models=True
        ),
    }


def test_the_course_files_give_the_course_listing():
    names = own_cell(LAUNCH, workspace=[FIXTURES / "group_ws" / "src"], environ={}).scenario.plugin_names
    assert names.camera_listings == {}
    assert names.camera_listing("logical_camera_1") == CameraListing()


def test_each_camera_lists_only_what_it_knows_named_as_the_plugin_names_it(workspace, tmp_path):
    """Under ``ros-run``: camera 1 lists the hall only (it sees the belt and its nested
    models too, and no part is spawned), its frame under their prefix and not the course's;
    camera 2 lists the bin and the belt as ``model``, not the belt's nested models, nor the
    pedestal or the hall it also sees."""
    from omtp_drake.cli import main

    seen, report = tmp_path / "seen.json", tmp_path / "report.json"
    argv = ["ros-run", str(EDITS / "watch_cameras.py"), str(seen), "--launch", LAUNCH]
    argv += ["--workspace", str(workspace), "--timeout", "30", "--json", str(report), "-q"]
    assert main(argv) == 0
    result = json.loads(report.read_text())
    assert result["exception"] is None, result["traceback"]
    seen_by = json.loads(seen.read_text())
    assert seen_by["logical_camera_1"] == ["workcell"]
    assert seen_by["logical_camera_2"] == ["model"]
    assert seen_by["course_frame"] is False and seen_by["bin_frame"] is True
    # The hall's origin, where their launch spawns it (no -x -y -z: the world's origin).
    assert max(abs(v) for v in seen_by["hall"]) < 1e-3, seen_by["hall"]


def _camera(xml: str):
    plugin = f'<plugin name="cam" filename="libROSLogicalCameraPlugin.so">{xml}</plugin>'
    return plugins_in(ET.fromstring(f"<model>{plugin}</model>"), "cams.world:12")[0]


def test_the_plugins_rules_name_as_ariac_does():
    """ModelToPublish: a known type or a known name; the frames and ids as ARIAC's helpers."""
    from pydrake.math import RigidTransform

    listing = PluginListing("cam", CameraListing(known_model_types=["object"], known_model_names=["bin_1_"]))
    assert [listing.publishes(n) for n in ("object_3", "object_clone_2", "bin_1_", "bin_2_", "robot1")] == [
        True,
        True,
        True,
        False,
        False,
    ]
    assert listing.model("object_3", RigidTransform(), RigidTransform()).frame == "cam_object_3_frame"
    anonymous = PluginListing("cam", CameraListing(anonymize_models=True, model_frame_prefix=""))
    seen = anonymous.model("object_12", RigidTransform(), RigidTransform())
    assert (seen.name, seen.type, seen.frame) == ("", "model", "model_12_frame")
    assert [model_id(n) for n in ("object_3", "robot2", "bin_1_", "a_3", "ns|part_7")] == [
        "3",
        "robot2",
        "",
        "a_3",
        "7",
    ]
    # Nested models: published by their own type and rules, never named.
    assert anonymous.nested("conveyor_belt_fixed", RigidTransform()).type == "conveyor_belt_fixed"


def test_a_types_list_without_types_stops_the_plugin_as_gazebo_does():
    entry, lines = camera_listing(_camera("<known_model_types/>"))
    assert entry == {"known_model_types": [], "advertised": False}
    (line,) = lines
    assert line.startswith("cams.world:12: ROSLogicalCameraPlugin (cam): Unable to find <type> elements")
    assert not PluginListing("c", CameraListing(**entry)).publishes("object_1")


@pytest.mark.parametrize(
    "xml, tag, valid",
    [
        ("<anonymize_models>maybe</anonymize_models>", "anonymize_models", "valid: true, false, 1, 0"),
        ("<model_frame_prefix>my cam</model_frame_prefix>", "model_frame_prefix", "valid: a tf frame prefix"),
    ],
)
def test_a_bad_value_is_one_error_naming_the_place_the_value_and_the_valid_choices(xml, tag, valid):
    with pytest.raises(WorkspaceError) as raised:
        camera_listing(_camera(xml))
    message = str(raised.value)
    assert message.startswith(f"cams.world:12: ROSLogicalCameraPlugin (cam) <{tag}>"), message
    assert repr(ET.fromstring(f"<x>{xml}</x>")[0].text) in message and valid in message
    assert "\n" not in message


def test_a_model_not_seen_yet_under_their_frame_prefix_is_said_so_not_unknown(workspace):
    """tf under their camera 1's ``model_frame_prefix`` (``belt_cam_``): a part it has not
    seen yet is "not seen" by that camera (what its images show), as under the course's
    prefix, not an unknown frame; the hall it sees is there."""
    from omtp_drake.errors import FrameError
    from omtp_drake.gazebo.logical_camera import camera_views
    from omtp_drake.script import Cell

    cell = Cell(launch=LAUNCH, workspace=[workspace], auto_spawn=False)
    try:
        views = camera_views(cell)
        cell.tf.use_images(lambda camera: views[camera].image_of)
        cell.wait(0.25)
        assert "belt_cam_workcell__frame" in cell.tf.all_frame_names()
        with pytest.raises(FrameError, match=r"logical_camera_1 has not seen 'object_1' \(its images from"):
            cell.tf.lookup_transform("world", "belt_cam_object_1_frame")
    finally:
        cell.close()


def test_the_camera_command_echoes_what_their_plugin_publishes(workspace, capsys):
    """``omtp-drake camera --launch``: the message of the camera's topic, by their plugin's
    rules: camera 2 the belt and the bin as two ``model``s (anonymized), not the pedestal
    it also sees; camera 1 only the hall and parts (their known types), not the belt."""
    from omtp_drake.cli import main

    listed = {}
    for camera in ("logical_camera_1", "logical_camera_2"):
        argv = ["camera", "--launch", LAUNCH, "--workspace", str(workspace), "--camera", camera]
        assert main([*argv, "--time", "1", "--json"]) == 0
        listed[camera] = [(m["name"], m["type"]) for m in json.loads(capsys.readouterr().out)["models"]]
    assert listed["logical_camera_2"] == [("", "model"), ("", "model")]
    assert ("workcell_", "workcell") in listed["logical_camera_1"]
    assert {t for _, t in listed["logical_camera_1"]} <= {"workcell", "object"}


def test_the_camera_command_of_a_camera_whose_plugin_stopped_is_one_line(tmp_path, capsys):
    from omtp_drake.cli import main

    scenario = tmp_path / "stopped.yaml"
    scenario.write_text(
        json.dumps(
            {
                "base": "lecture6_assignment1",
                "plugin_names": {
                    "camera_listings": {"logical_camera_1": {"known_model_types": [], "advertised": False}}
                },
            }
        )
    )
    assert main(["camera", str(scenario), "--camera", "logical_camera_1"]) == 2
    err = capsys.readouterr().err
    assert "logical camera 'logical_camera_1' publishes nothing" in err and err.count("\n") == 1


def test_an_agvs_kit_tray_is_a_tf_frame_under_it_not_in_the_message():
    """ARIAC's AGV in the plugin: a model of type ``agv1`` in view gets its kit tray's
    frame, 0.15 m along its y and 0.75 m up, under its own; the message lists the AGV only.
    With the camera's noise on, the plugin noises the tray, not the AGV: the AGV where it
    stands, the tray off its 0.15/0.75 by the camera's draw (the Python layer's image has
    the same draw on the AGV)."""
    import dataclasses

    import numpy as np

    from omtp_drake.gazebo.logical_camera import camera_views
    from omtp_drake.scenario import ModelConfig, load_scenario
    from omtp_drake.script import Cell

    box = (
        '<robot name="agv1"><link name="agv1_base"><visual><geometry><box size="0.3 0.3 0.1"/>'
        '</geometry></visual><collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision>'
        "</link></robot>"
    )
    scenario = load_scenario("lecture6_assignment1")
    agv = ModelConfig(name="agv1", file="agv1.urdf", description=box, xyz=[1.2, 1.6, 1.2], static=True)
    noisy = {"position_noise_sigma": 0.02, "orientation_noise_sigma": 0.05}
    cameras = [dataclasses.replace(c, **noisy) for c in scenario.cameras]
    scenario = dataclasses.replace(scenario, models=[*scenario.models, agv], cameras=cameras)
    cell = Cell(scenario, auto_spawn=False)
    try:
        views = camera_views(cell)
        cell.tf.use_images(lambda camera: views[camera].image_of)
        cell.wait(0.25)
        image = views["logical_camera_1"].image(cell.runtime.context)
        assert ("agv1", "agv1") in [(m.name, m.type) for m in image.models]
        assert not [m for m in image.models if "kit_tray" in m.type]
        (published,) = [m for m in image.models if m.name == "agv1"]
        X_WA = image.X_WC @ published.X_CM
        np.testing.assert_allclose(X_WA.translation(), [1.2, 1.6, 1.2], atol=1e-9)
        assert X_WA.rotation().IsNearlyIdentity(1e-9)
        (own,) = [m for m in cell.runtime.camera_image("logical_camera_1").models if m.name == "agv1"]
        dp = own.X_CM.translation() - published.X_CM.translation()  # the camera's draw for it
        assert np.linalg.norm(dp) > 1e-3
        X_WT = cell.tf.lookup_transform("world", "logical_camera_1_kit_tray_1_frame").transform
        X_AT = X_WA.inverse() @ X_WT
        np.testing.assert_allclose(X_AT.translation(), np.array([0.0, 0.15, 0.75]) + dp, atol=1e-6)
        R_pert = published.X_CM.rotation().inverse() @ own.X_CM.rotation()  # AddNoise: Rot *= pert
        assert not R_pert.IsNearlyIdentity(1e-3)
        np.testing.assert_allclose(X_AT.rotation().matrix(), R_pert.matrix(), atol=1e-6)
    finally:
        cell.close()
