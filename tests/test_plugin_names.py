"""A student's ``<plugin>`` parameters name the course's plugins' topics and services
(tests/fixtures/renamed_topics laid over a copy of tests/fixtures/group_ws): read once into
the scenario's ``plugin_names``, served under those names by ``ros-run`` (a course-style
rospy script picks a part into their bin on them) and by ``omtp-drake ros2`` (a plain rclpy
node sees them on the graph, and not the course's defaults). The ROS 2 cell is shared with
tests/test_camera_listings.py's ROS 2 test (the module's fixture ``ros2_seen``: its camera
edits and these in one workspace; each test reads what its own node saw)."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from fixture_reports import assert_as_recorded
from test_ros2 import SCRIPTS, hold_domain, needs_ros2, run_cell_with_nodes

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch import own_cell
from omtp_drake.launch.plugins import beam_names, conveyor_service, gripper_names, plugins_in

FIXTURES = Path(__file__).resolve().parent / "fixtures"
EDITS = FIXTURES / "renamed_topics"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
#: Where each edit goes in the workspace.
OVERLAY = {
    "vacuum_gripper.gazebo.xacro": "omtp_support/urdf/vacuum_gripper/vacuum_gripper.gazebo.xacro",
    "break_beam.gazebo.xacro": "omtp_support/urdf/break_beam/break_beam.gazebo.xacro",
    "conveyor.sdf": "omtp_gazebo/models/conveyor/model.sdf",
    "logical_camera2.sdf": "omtp_gazebo/models/logical_camera2/model.sdf",
}


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    src = tmp_path_factory.mktemp("renamed") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    for edit, target in OVERLAY.items():
        shutil.copyfile(EDITS / edit, src / target)
    return src


#: tests/test_camera_listings.py's edits: its camera 1, and its camera 2 on this module's topic.
LISTINGS = FIXTURES / "camera_listings"


@pytest.fixture(scope="module")
def ros2_seen(workspace, tmp_path_factory) -> dict:
    """One ``omtp-drake ros2`` cell of LAUNCH on a copy of the workspace with camera_listings'
    cameras too (camera 2 keeps this module's topic, /cell/bin_camera), and in turn: a node
    listing the graph's names, then a node reading the cameras' markers. What each saw, by name
    ("graph", "markers")."""
    src = tmp_path_factory.mktemp("names_and_listings") / "src"
    shutil.copytree(workspace, src)
    cameras = src / "omtp_gazebo" / "models"
    shutil.copyfile(LISTINGS / "logical_camera1.sdf", cameras / "logical_camera1" / "model.sdf")
    camera2 = (LISTINGS / "logical_camera2.sdf").read_text()
    renamed = "<robotNamespace>cell</robotNamespace><image_topic_ros>bin_camera</image_topic_ros>"
    camera2 = camera2.replace("<robotNamespace>omtp</robotNamespace>", renamed)
    assert renamed in camera2
    (cameras / "logical_camera2" / "model.sdf").write_text(camera2)
    out = {name: src.parent / f"{name}.json" for name in ("graph", "markers")}
    wanted = ["/cell/gripper1/my_state", "/cell/beam/state", "/cell/gripper1/suction", "/omtp/belt/power"]
    wanted += ["/cell/bin_camera/poses"]
    markers = ["logical_camera_1", "logical_camera_2:/cell/bin_camera"]
    nodes = [[str(SCRIPTS / "graph_names_node.py"), str(out["graph"]), *wanted]]
    nodes.append([str(SCRIPTS / "camera_markers_node.py"), str(out["markers"]), *markers])
    with hold_domain() as domain:
        run_cell_with_nodes(["--launch", LAUNCH, "--workspace", str(src)], nodes, domain)
    return {name: json.loads(path.read_text()) for name, path in out.items()}


def test_their_parameters_are_read_once_into_the_scenario(workspace):
    names = own_cell(LAUNCH, workspace=[workspace], environ={}).scenario.plugin_names
    assert [(g.robot, g.plugin, g.control_service, g.state_topic) for g in names.grippers] == [
        ("robot1", "gripper1", "/cell/gripper1/suction", "/cell/gripper1/my_state"),
        ("robot2", "gripper2", "/cell/gripper2/suction", "/cell/gripper2/my_state"),
    ]
    assert (names.beam_state_topic, names.beam_change_topic) == ("/cell/beam/state", "/cell/beam/change")
    assert names.beam_frame_id == "break_beam_optical_link"
    assert names.conveyor_control_service == "/omtp/belt/power"
    assert names.camera_topics == {"logical_camera_2": "/cell/bin_camera"}  # camera 1's: the course's
    assert names.camera_topic("logical_camera_1") == "/omtp/logical_camera_1"


def test_a_rospy_script_on_their_names_picks_a_part_into_their_bin(workspace, tmp_path):
    from omtp_drake.cli import main

    seen, report = tmp_path / "seen.json", tmp_path / "report.json"
    argv = ["ros-run", str(EDITS / "pick_one_renamed.py"), str(seen), "--launch", LAUNCH]
    argv += ["--workspace", str(workspace), "--timeout", "60", "--json", str(report), "-q"]
    assert main(argv) == 0
    result = json.loads(report.read_text())
    assert result["exception"] is None, result["traceback"]
    assert result["ledger"]["in_bin"]["bin_2"] == 1, result["ledger"]
    assert_as_recorded("renamed_topics pick_one_renamed.py", result)
    assert json.loads(seen.read_text()) == {
        "enabled": True,
        "attached": True,
        "beam_frames": ["break_beam_optical_link"],
        "bin_camera": True,
    }


@needs_ros2
def test_the_ros2_graph_has_their_names_and_not_the_courses(ros2_seen):
    graph = ros2_seen["graph"]
    assert graph["topics"]["/cell/gripper1/my_state"] == ["omtp_gazebo/msg/VacuumGripperState"]
    assert graph["topics"]["/cell/beam/state"] == ["omtp_gazebo/msg/Proximity"]
    assert "/cell/beam/change" in graph["topics"]
    assert graph["services"]["/cell/gripper1/suction"] == ["std_srvs/srv/SetBool"]
    assert graph["services"]["/omtp/belt/power"] == ["std_srvs/srv/SetBool"]
    assert graph["topics"]["/cell/bin_camera/poses"] == ["geometry_msgs/msg/PoseArray"]
    old = {"/gripper1/state", "/break_beam_sensor", "/gripper1/control", "/omtp/conveyor/control"}
    old |= {"/omtp/logical_camera_2/poses"}
    assert not old & (set(graph["topics"]) | set(graph["services"]))


def _plugin(xml: str):
    return plugins_in(ET.fromstring(f"<gazebo>{xml}</gazebo>"), "robot.xacro:7")[0]


def test_without_parameters_the_plugins_defaults():
    """The plugins' own defaults (the course's files set the names; a file that does not
    gets these, as Gazebo would)."""
    gripper = _plugin('<plugin name="g" filename="libROSVacuumGripperPlugin.so"/>')
    assert gripper_names(gripper, "robot1")["control_service"] == "/gripper/control"
    assert gripper_names(gripper, "robot1")["state_topic"] == "/gripper/state"
    beam = _plugin(
        '<sensor name="eye" type="ray"><plugin name="b" filename="libROSProximityRayPlugin.so"/></sensor>'
    )
    assert beam_names(beam) == {
        "beam_state_topic": "/eye",
        "beam_change_topic": "/eye_change",
        "beam_frame_id": "eye_frame",
    }
    belt = _plugin('<plugin name="c" filename="libROSConveyorBeltPlugin.so"><topic>/belt</topic></plugin>')
    assert conveyor_service(belt) == "/belt"


@pytest.mark.parametrize(
    "xml, tag",
    [
        ("<state_topic>my gripper/state</state_topic>", "state_topic"),
        ("<control_topic>~control</control_topic>", "control_topic"),
        ("<robot_namespace>2cell</robot_namespace>", "robot_namespace"),
    ],
)
def test_a_bad_name_is_one_error_naming_the_place_the_value_and_the_valid_choices(xml, tag):
    plugin = _plugin(f'<plugin name="gripper1" filename="libROSVacuumGripperPlugin.so">{xml}</plugin>')
    with pytest.raises(WorkspaceError) as raised:
        gripper_names(plugin, "robot1")
    message = str(raised.value)
    assert message.startswith(f"robot.xacro:7: libROSVacuumGripperPlugin.so (gripper1) <{tag}>"), message
    assert ET.fromstring(f"<x>{xml}</x>")[0].text in message and "valid: a ROS name" in message
    assert "\n" not in message


@needs_ros2
def test_on_ros2_each_camera_lists_only_what_it_knows_named_as_the_plugin_names_it(ros2_seen):
    """``omtp-drake ros2`` (tests/test_camera_listings.py's rules, camera 2 on its renamed topic):
    the cameras' rviz2 markers label what the plugin publishes (a model's name, or its type when
    anonymized): camera 1 the hall only, camera 2 two ``model``s (the belt and the bin)."""
    assert ros2_seen["markers"] == {
        "logical_camera_1": ["workcell_"],
        "logical_camera_2": ["model", "model"],
    }
