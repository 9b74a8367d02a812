"""The URDF tutorial's robot (tests/fixtures/tutorial_ws: a slider, an arm and a depth
camera, with Gazebo's plugins) under ``omtp-drake ros2 ROBOT``, and a plain rclpy node in
another process (tests/ros2_scripts/tutorial_node.py): /joint_states names the joints of
the model's joint state publisher, /set_joint_trajectory plays as Gazebo's plugin plays
it, and the depth camera's topics arrive. The same trajectory under ``ros-run``
(tests/ros2_scripts/ros1_tutorial_script.py, rospy) gives the same samples: one plugin
layer, two transports.

Verdicts count in simulated time (stamps), never in wall-clock rates. DDS stays on
loopback, in a domain of the test's own, and no process is left behind.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from test_ros2 import (
    hold_domain,
    needs_ros2,
    run_cell_with_node,
)

SCRIPTS = Path(__file__).parent / "ros2_scripts"
FIXTURE = Path(__file__).parent / "fixtures" / "tutorial_ws"
ROBOT = FIXTURE / "src" / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
#: The trajectory's stamp START (simulated s) is chosen by the node once it hears the cell
#: (its /clock, a /joint_states message, a subscriber of its trajectory: DDS discovery is
#: over, however long it took): the first whole half second at least LEAD after that /clock,
#: so that the recording of [START - 1, END] is already under way and the trajectory has over
#: 0.5 simulated s (wall s: the cell is paced, --realtime) to reach the cell. The recording
#: ends at END = START + SPAN. (A fixed START of 5 s, for the worst discovery, paced every
#: run to 6.5 s.)
LEAD, SPAN = 1.5, 1.5
SPEC = json.loads((SCRIPTS / "trajectory.json").read_text())
#: The plugins' rates in the fixture: joint states 20 Hz, trajectory updates 2 Hz, camera 20 Hz.
STATE_PERIOD, CAMERA_PERIOD = 0.05, 0.05


def _ros2(tmp_path: Path, domain: int) -> tuple[dict, str]:
    out = tmp_path / "seen.json"
    node = [str(SCRIPTS / "tutorial_node.py"), str(out), str(LEAD), str(SPAN)]
    _, cell_err = run_cell_with_node([str(ROBOT), "--realtime"], node, domain)
    return json.loads(out.read_text()), cell_err


def _ros1(tmp_path: Path, start: float, end: float) -> dict:
    from omtp_drake.ros.run.runner import run_script

    out = tmp_path / "ros1.json"
    report = run_script(
        SCRIPTS / "ros1_tutorial_script.py", [str(out), str(start), str(end)],
        robot=ROBOT, workspace=[FIXTURE / "src"], timeout=end + 2.0,
    )  # fmt: skip
    assert report.exception is None, report.exception
    return json.loads(out.read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """(what the rclpy node saw, the cell's stderr, what the rospy script saw: the same
    trajectory, stamped the node's START)."""
    tmp = tmp_path_factory.mktemp("tutorial")
    with hold_domain() as held:
        seen, cell_err = _ros2(tmp, held)
    assert seen["start"] >= seen["sent_at"] + LEAD and seen["end"] == seen["start"] + SPAN
    return seen, cell_err, _ros1(tmp, seen["start"], seen["end"])


def _samples(states: list, lo: float, hi: float) -> dict[float, dict[str, float]]:
    """Stamp (rounded to 1 ms) -> joint -> position, of the messages stamped in [lo, hi]."""
    return {round(t, 3): dict(zip(names, q)) for t, names, q in states if lo - 1e-9 <= t <= hi + 1e-9}


@needs_ros2
def test_joint_states_name_the_plugins_joints_at_its_rate(runs):
    seen, _, _ = runs
    START, END = seen["start"], seen["end"]
    assert seen["states"], "no /joint_states"
    assert all(names == ["slider_joint", "arm_joint"] for _, names, _ in seen["states"])
    # 20 Hz in simulated time: every 50 ms stamp of [START - 1, END - 0.5], each once.
    stamps = [round(t, 3) for t, _, _ in seen["states"] if START - 1.0 <= t <= END - 0.5]
    expected = np.round(np.arange(START - 1.0, END - 0.5 + 1e-9, STATE_PERIOD), 3).tolist()
    assert stamps == expected


@needs_ros2
def test_robot_description_is_the_robots_urdf_under_world(runs):
    import xml.etree.ElementTree as ET

    seen, _, _ = runs
    root = ET.fromstring(seen["description"].split("\n", 1)[1])
    links = [link.get("name") for link in root.findall("link")]
    joints = {j.get("name"): j.get("type") for j in root.findall("joint")}
    assert joints["slider_joint"] == "prismatic" and joints["arm_joint"] == "revolute"
    children = {j.find("child").get("link") for j in root.findall("joint")}
    assert len(links) == len(set(links)) and [n for n in links if n not in children] == ["world"]


@needs_ros2
def test_set_joint_trajectory_plays_as_gazebos_plugin(runs):
    seen, cell_err, _ = runs
    START, END = seen["start"], seen["end"]
    assert seen["sent_at"] < START - 1.0, "the node sent the trajectory too late to test its stamp"
    (first, _), (bad, _), (last, _) = SPEC["points"]
    q = _samples(seen["states"], START - 1.0, END)
    before = [s for t, s in q.items() if t < START]
    assert all(abs(s["slider_joint"] - first[0]) > 0.1 for s in before)
    # Point 0 at the stamp; the bad point (one position for two joints) is skipped with the
    # plugin's error 0.5 s later; the last point 0.5 s after that.
    at = {t: s for t, s in q.items() if START <= t < START + 1.0}
    assert all(abs(s["slider_joint"] - first[0]) < 0.02 for s in at.values()), at
    assert not any(abs(s["slider_joint"] - bad[0]) < 0.02 for s in q.values())
    after = {t: s for t, s in q.items() if t >= START + 1.0}
    assert after and all(abs(s["slider_joint"] - last[0]) < 0.02 for s in after.values()), after
    assert "point[2] has different number of joint names[2] and positions[1]" in cell_err


@needs_ros2
def test_both_transports_give_the_same_samples(runs):
    """One trajectory, ``ros-run`` (ROS 1) and ``ros2``: the same stamps, the same positions."""
    seen, _, ros1 = runs
    START, END = seen["start"], seen["end"]
    assert ros1["sent_at"] < START
    a = _samples(seen["states"], START - 1.0, END - 0.5)
    b = _samples(ros1["states"], START - 1.0, END - 0.5)
    assert sorted(a) == sorted(b) and len(a) == round((END - 0.5 - START + 1.0) / STATE_PERIOD) + 1
    worst = max(abs(a[t][j] - b[t][j]) for t in a for j in ("slider_joint", "arm_joint"))
    assert worst < 1e-6, worst


@needs_ros2
def test_the_depth_camera_topics_arrive(runs):
    seen, _, _ = runs
    camera = seen["camera"]
    for name, info in camera.items():
        assert info["frame_id"] == "camera_link_optical" and info["size"] == [640, 480], name
        assert abs(info["stamp"] / CAMERA_PERIOD - round(info["stamp"] / CAMERA_PERIOD)) < 1e-6, name
    assert camera["/tip_camera/image_raw"]["encoding"] == "rgb8"
    assert camera["/tip_camera/image_raw"]["bytes"] == 640 * 480 * 3
    assert camera["/tip_camera/depth/image_raw"]["encoding"] == "32FC1"
    points = camera["/tip_camera/points"]
    assert points["point_step"] == 32 and points["bytes"] == 640 * 480 * 32
    assert points["fields"] == [["x", 0], ["y", 4], ["z", 8], ["rgb", 16]]
    k = camera["/tip_camera/camera_info"]["k"]
    assert k[2] == pytest.approx((640 + 1) / 2) and k[5] == pytest.approx((480 + 1) / 2)
