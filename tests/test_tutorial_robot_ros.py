"""The tutorial's robot under ``ros-run --robot``: a course-style rospy script moves it with
/set_joint_trajectory and watches /joint_states; its depth camera's topics."""

import json
import logging
from pathlib import Path

import numpy as np
import pytest
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RigidTransform

from omtp_drake.ros.comm.image_messages import PointCloud2, PointField, read_points
from omtp_drake.ros.run.runner import run_script

FIXTURE = Path(__file__).parent / "fixtures" / "tutorial_ws"
ROBOT = FIXTURE / "src" / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
SCRIPT = FIXTURE / "scripts" / "move_slider_arm.py"
FLOOR_Z, PLATE_TOP_Z, PLATE_HALF, FLOOR_HALF = 0.0, 0.08, (1.0, 0.6), 10.05


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "result.json"
    report = run_script(SCRIPT, [str(out)], robot=ROBOT, workspace=[FIXTURE / "src"], timeout=20.0)
    return report, json.loads(out.read_text()), np.load(str(out) + ".points.npy")


def test_the_trajectory_is_reached_and_joint_states_say_so(run):
    report, result, _ = run
    assert report.exception is None and report.scenario == "empty_world"
    reached = result["reached"]
    assert reached is not None
    assert reached["positions"]["slider_joint"] == pytest.approx(0.8, abs=0.02)
    assert reached["positions"]["arm_joint"] == pytest.approx(0.6, abs=0.02)
    # The plugin updates at 2 Hz: the point is set at the first update after the message.
    assert result["sent"] < reached["t"] <= result["sent"] + 0.5 + 1e-6


def test_the_depth_camera_topics(run):
    _, result, points = run
    assert result["image"] == [640, 480, "rgb8"]
    assert result["cloud"] == [640, 480, "camera_link_optical"]
    assert points.shape == (640 * 480, 3)


def test_the_points_lie_on_the_floor_and_the_plate(run):
    _, result, p_OP = run
    x, y, z, qx, qy, qz, qw = result["X_WO"]
    X_WO = RigidTransform(Quaternion(qw, qx, qy, qz), [x, y, z])
    seen = np.isfinite(p_OP).all(axis=1)
    assert seen.sum() > 100_000
    p_WP = X_WO.multiply(p_OP[seen].T.astype(float))
    p_WP = p_WP[:, (np.abs(p_WP[:2]) < FLOOR_HALF - 0.01).all(axis=0)]  # not the slab's sides
    on_plate = (np.abs(p_WP[0]) <= PLATE_HALF[0] + 0.01) & (np.abs(p_WP[1]) <= PLATE_HALF[1] + 0.01)
    expected = np.where(on_plate & (p_WP[2] > 0.04), PLATE_TOP_Z, FLOOR_Z)
    assert np.abs(p_WP[2] - expected).max() < 0.01


def test_read_points_reads_the_fields_by_name():
    data = np.array([[1, 2, 3, 0, 0, 0, 0, 0], [4, 5, np.nan, 0, 0, 0, 0, 0]], dtype=np.float32).tobytes()
    fields = [
        PointField(name=n, offset=o, datatype=PointField.FLOAT32, count=1)
        for n, o in (("x", 0), ("y", 4), ("z", 8))
    ]
    cloud = PointCloud2(height=1, width=2, fields=fields, point_step=32, row_step=64, data=data)
    assert list(read_points(cloud, ("z", "x"), skip_nans=True)) == [(3.0, 1.0)]
    assert list(read_points(cloud, uvs=[(1, 0)]))[0][:2] == (4.0, 5.0)


def test_an_unknown_plugin_is_one_warning_line(tmp_path, caplog):
    robot = tmp_path / "r.urdf"
    robot.write_text(
        '<robot name="r"><link name="a"><inertial><mass value="1"/>'
        '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<gazebo><plugin name="drive" filename="libgazebo_ros_diff_drive.so"/></gazebo></robot>'
    )
    script = tmp_path / "idle.py"
    script.write_text("import rospy\nrospy.init_node('idle')\nrospy.sleep(0.1)\n")
    with caplog.at_level(logging.WARNING, logger="gazebo"):
        report = run_script(script, robot=robot, timeout=5.0)
    assert report.exception is None
    lines = [r.getMessage() for r in caplog.records if "libgazebo_ros_diff_drive.so" in r.getMessage()]
    assert lines == [f"{robot}: plugin 'drive' (libgazebo_ros_diff_drive.so) is not simulated; ignored"]
    assert report.ignored_plugins == lines
    assert f"ignored plugin: {lines[0]}" in report.summary().splitlines()


def test_with_the_ur_arms_joint_states_has_both_publishers(tmp_path):
    script = tmp_path / "echo.py"
    out = tmp_path / "names.json"
    script.write_text(
        "import json, sys, rospy\nfrom sensor_msgs.msg import JointState\nrospy.init_node('echo')\n"
        "names = set()\n"
        "rospy.Subscriber('/joint_states', JointState, lambda m: names.add(tuple(m.name)), queue_size=10)\n"
        "rospy.sleep(0.3)\n"
        "json.dump(sorted(names), open(sys.argv[1], 'w'))\n"
    )
    report = run_script(script, [str(out)], scenario="omtp_factory", robot=ROBOT, timeout=10.0)
    assert report.exception is None
    names = json.loads(out.read_text())
    assert ["slider_joint", "arm_joint"] in names
    assert any(n[0] == "robot1_shoulder_pan_joint" for n in names)
