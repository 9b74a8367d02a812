"""``omtp-drake view``: the tutorial robot's joints, frames, sensors and plugins as parsed
(``--json``), its sliders, and a screenshot."""

import json
from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import Meshcat

from omtp_drake.cli import main
from omtp_drake.scenario import model_from_file
from omtp_drake.viz.browser import find_browser
from omtp_drake.viz.model_view import build_model_view

ROBOT = Path(__file__).parent / "fixtures" / "tutorial_ws" / "src" / "slider_arm_description" / "urdf"
ROBOT = ROBOT / "slider_arm.urdf.xacro"


@pytest.fixture(scope="module")
def listed(tmp_path_factory):
    out = tmp_path_factory.mktemp("view") / "model.json"
    assert main(["view", str(ROBOT), "--json", str(out)]) == 0
    return json.loads(out.read_text())


def test_json_lists_the_joints_with_types_axes_and_limits(listed):
    joints = {j["name"]: j for j in listed["joints"]}
    assert {n: j["type"] for n, j in joints.items()} == {
        "plate_joint": "fixed",
        "slider_joint": "prismatic",
        "arm_joint": "revolute",
        "camera_joint": "fixed",
        "camera_optical_joint": "fixed",
    }
    assert joints["slider_joint"]["axis"] == [1.0, 0.0, 0.0]
    assert joints["slider_joint"]["limits"] == {
        "lower": 0.0,
        "upper": pytest.approx(1.6),
        "velocity": 1.0,
        "effort": 50.0,
    }
    assert joints["arm_joint"]["axis"] == [0.0, -1.0, 0.0]
    assert joints["arm_joint"]["limits"]["upper"] == pytest.approx(np.pi / 2)
    assert (joints["arm_joint"]["parent"], joints["arm_joint"]["child"]) == ("slider_link", "arm_link")


def test_json_lists_links_frames_sensors_and_plugins(listed):
    assert listed["links"] == ["base_link", "slider_link", "arm_link", "camera_link", "camera_link_optical"]
    assert {"name": "camera_link_optical", "body": "camera_link_optical"} in listed["frames"]
    (sensor,) = listed["sensors"]
    assert (sensor["name"], sensor["type"], sensor["camera"]["width"]) == ("tip_camera", "depth", 640)
    kinds = sorted(p["kind"] for p in listed["plugins"])
    assert kinds == ["camera", "joint_pose_trajectory", "joint_state_publisher"]


def test_a_slider_per_movable_joint_within_its_limits():
    meshcat = Meshcat()
    view = build_model_view(model_from_file(ROBOT, static=True), meshcat, {"arm_joint": 0.5})
    assert sorted(meshcat.GetSliderNames()) == ["arm_joint", "slider_joint"]
    assert meshcat.GetSliderValue("arm_joint") == pytest.approx(0.5)
    view.publish()  # draws the images and the point cloud
    assert meshcat.HasPath("/drake/tip_camera/points") and meshcat.HasPath("/images/tip_camera/depth")


def test_meshcat_is_sent_the_finite_points_with_their_colours():
    """A depth image's pixels with no depth give points at infinity or NaN: not drawn, not sent."""
    from pydrake.perception import BaseField, Fields, PointCloud

    from omtp_drake.cell.depth_camera import FinitePoints

    cloud = PointCloud(3, Fields(BaseField.kXYZs | BaseField.kRGBs))
    cloud.mutable_xyzs()[:] = [[np.inf, 0.5, np.nan], [0.0, 0.1, 0.0], [0.0, 2.0, 0.0]]
    cloud.mutable_rgbs()[:] = [[10, 20, 30], [11, 21, 31], [12, 22, 32]]
    system = FinitePoints()
    context = system.CreateDefaultContext()
    system.get_input_port().FixValue(context, cloud)
    finite = system.get_output_port().Eval(context)
    np.testing.assert_allclose(finite.xyzs(), [[0.5], [0.1], [2.0]], rtol=1e-6)
    assert finite.rgbs().ravel().tolist() == [20, 21, 22]


def test_a_position_outside_the_limits_is_one_error(capsys):
    assert main(["view", str(ROBOT), "--screenshot", "x.png", "--position", "arm_joint=2.0"]) == 2
    assert "joint 'arm_joint': position 2.0 is outside its limits" in capsys.readouterr().err


@pytest.mark.skipif(find_browser() is None, reason="no chromium")
def test_screenshot(tmp_path):
    png = tmp_path / "view.png"
    assert main(["view", str(ROBOT), "--screenshot", str(png), "--position", "slider_joint=0.8"]) == 0
    from matplotlib.image import imread

    image = imread(png)
    assert image.shape[:2] == (800, 1280)
    assert image[..., :3].std() > 0.05  # the model and panels, not an empty page


def test_images_writes_the_camera_images_and_points(tmp_path):
    args = ["view", str(ROBOT), "--images", str(tmp_path), "--position", "arm_joint=0.2"]
    assert main(args) == 0
    from matplotlib.image import imread

    assert imread(tmp_path / "tip_camera_color.png").shape[:2] == (480, 640)
    assert imread(tmp_path / "tip_camera_depth.png").shape[:2] == (480, 640)
    lines = (tmp_path / "tip_camera_points.ply").read_text().splitlines()
    count = int(next(line for line in lines if line.startswith("element vertex")).split()[-1])
    assert count > 50_000 and len(lines) == count + 10  # the ground below the horizon


SDF = """<?xml version="1.0"?>
<sdf version="1.7"><model name="camera_box">
  <link name="body"><pose>0 0 0.5 0 0 0</pose>
    <inertial><mass>1</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial>
    <visual name="v"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></visual>
    <sensor name="cam" type="camera"><update_rate>10</update_rate>
      <camera><horizontal_fov>1.0</horizontal_fov><image><width>320</width><height>240</height></image>
        <clip><near>0.15</near><far>20</far></clip></camera>
      <plugin name="drv" filename="libgazebo_ros_camera.so"><camera_name>boxcam</camera_name></plugin>
    </sensor></link>
  <link name="lid"><pose>0 0 0.7 0 0 0</pose>
    <inertial><mass>0.1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial></link>
  <joint name="hinge" type="revolute"><parent>body</parent><child>lid</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
</model></sdf>
"""


def test_an_sdf_model_with_a_camera(tmp_path, capsys):
    path = tmp_path / "camera_box.sdf"
    path.write_text(SDF)
    assert main(["view", str(path), "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert listed["links"] == ["body", "lid"]
    assert [(j["name"], j["type"], j["axis"]) for j in listed["joints"]] == [
        ("hinge", "revolute", [0.0, 1.0, 0.0])
    ]
    assert listed["sensors"][0]["ros_camera"]["camera_name"] == "boxcam"


def test_a_plugin_value_out_of_range_exits_2_with_one_line(tmp_path, capsys):
    path = tmp_path / "camera_box.sdf"
    path.write_text(
        SDF.replace("<horizontal_fov>1.0</horizontal_fov>", "<horizontal_fov>3.2</horizontal_fov>")
    )
    assert main(["view", str(path), "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert (
        err.count("\n") == 0 and str(path) in err and "horizontal_fov must be in (0, pi) rad, got 3.2" in err
    )


def test_a_launchs_robot_description_is_viewed_as_rviz_shows_it(tmp_path, listed):
    """``view --launch``: the URDF a display launch loads on /robot_description (rviz's
    default), the same joints as viewing the file itself."""
    out = tmp_path / "launch.json"
    workspace = str(ROBOT.parents[3])
    launch = "slider_arm_description display.launch gui:=false"
    assert main(["view", "--launch", launch, "--workspace", workspace, "--json", str(out)]) == 0
    from_launch = json.loads(out.read_text())
    assert from_launch["joints"] == listed["joints"] and from_launch["links"] == listed["links"]


def test_a_launch_without_that_parameter_names_the_ones_it_has(capsys):
    workspace = str(ROBOT.parents[3])
    launch = "slider_arm_description display.launch"
    args = ["--workspace", workspace, "--param", "robot2_description", "--json"]
    code = main(["view", "--launch", launch, *args])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1
    assert "display.launch: loads no robot description on /robot2_description" in err[0]
    assert "description parameters: /robot_description" in err[0]
