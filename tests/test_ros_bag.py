"""``--bag run.mcap``: a ROS 1 session (``ros-run``) recorded as a ROS 2 bag: it opens with
mcap's reader and holds /clock, /joint_states, /tf, the logical cameras' topics and the
script's own, in ROS 2's types, with monotonic simulated stamps."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mcap_ros2", reason='the ros2 extra is not installed: pip install -e ".[ros2]"')

#: A course-style script: it publishes a topic of its own and waits in simulated time.
SCRIPT = """\
import rospy
from std_msgs.msg import String

rospy.init_node("talker")
pub = rospy.Publisher("/chatter", String, queue_size=1)
for i in range(3):
    rospy.sleep(0.5)
    pub.publish(String(data="hello %d" % i))
"""


@pytest.fixture(scope="module")
def bag(tmp_path_factory):
    """(topic -> [(log time, publish time, decoded message)], topic -> schema name) of one run."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    from omtp_drake.ros import run_script

    folder = tmp_path_factory.mktemp("bag")
    script = folder / "talker.py"
    script.write_text(SCRIPT)
    path = folder / "run.mcap"
    report = run_script(script, scenario="lecture6_assignment4", bag=path, settle_after=0)
    assert report.ok, report.summary()
    with path.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None
        types = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
        messages: dict[str, list] = {}
        for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            messages.setdefault(channel.topic, []).append((message.log_time, message.publish_time, decoded))
    return messages, types


def test_the_bag_holds_the_runs_topics_in_ros2_types(bag):
    messages, types = bag
    assert types["/clock"] == "rosgraph_msgs/msg/Clock"
    assert types["/joint_states"] == "sensor_msgs/msg/JointState"
    assert types["/tf"] == types["/tf_static"] == "tf2_msgs/msg/TFMessage"
    assert types["/omtp/logical_camera_2"] == "omtp_gazebo/msg/LogicalCameraImage"
    assert types["/chatter"] == "std_msgs/msg/String"
    assert [m.data for _, _, m in messages["/chatter"]] == ["hello 0", "hello 1", "hello 2"]
    assert [t for t, _, _ in messages["/chatter"]] == [500_000_000, 1_000_000_000, 1_500_000_000]
    joints = messages["/joint_states"][-1][2]
    assert "robot1_shoulder_pan_joint" in joints.name and len(joints.position) == len(joints.name)
    assert not hasattr(joints.header, "seq")  # ROS 2's header
    # The course's logical camera: the models it sees (the belt among them).
    image = messages["/omtp/logical_camera_2"][-1][2]
    assert any(m.type == "conveyor_belt" for m in image.models), image


def test_the_stamps_are_simulated_and_monotonic(bag):
    messages, _ = bag
    for topic, entries in messages.items():
        logs = [t for t, _, _ in entries]
        stamps = [t for _, t, _ in entries]
        assert logs == sorted(logs), topic
        assert stamps == sorted(stamps) and all(s <= t for s, t in zip(stamps, logs)), topic
    clock = messages["/clock"]
    assert len(clock) >= 150  # 100 Hz for the script's 1.5 s
    assert all(m.clock.sec * 10**9 + m.clock.nanosec == t for t, _, m in clock)
    tf = messages["/tf"]
    assert np.allclose(np.diff([t for t, _, _ in tf]), 2e7, atol=1e3)  # 50 Hz
    for _, stamp, message in tf:
        moving = [x for x in message.transforms if not x.header.frame_id.startswith("logical_camera")]
        assert moving and all(x.header.stamp.sec * 10**9 + x.header.stamp.nanosec == stamp for x in moving)


def test_tf_static_and_tf_give_the_arms_links(bag):
    """robot2's tool0 from /tf_static and the last /tf, where the plant had it (the arm holds its home)."""
    from omtp_drake.cell.frames import FrameTree
    from omtp_drake.scenario import load_scenario
    from omtp_drake.sim.runtime import FactoryRuntime

    messages, _ = bag
    edges = {}
    for _, _, message in [messages["/tf_static"][0], messages["/tf"][-1]]:
        for x in message.transforms:
            t, q = x.transform.translation, x.transform.rotation
            edges[x.child_frame_id] = (x.header.frame_id, np.array([t.x, t.y, t.z]), (q.w, q.x, q.y, q.z))
    from pydrake.common.eigen_geometry import Quaternion
    from pydrake.math import RigidTransform

    X = RigidTransform()
    name = "robot2_tool0"
    while name != "world":
        name, p, q = edges[name]
        X = RigidTransform(Quaternion(*q), p) @ X
    runtime = FactoryRuntime(load_scenario("lecture6_assignment4"))
    runtime.advance_to(messages["/tf"][-1][1] / 1e9)
    tree = FrameTree(runtime.station.plant)
    X_expected = tree.frame("robot2_tool0").CalcPoseInWorld(
        runtime.station.plant.GetMyContextFromRoot(runtime.context)
    )
    assert np.linalg.norm(X.translation() - X_expected.translation()) < 1e-3


def test_a_run_that_fails_in_its_set_up_leaves_a_readable_bag(tmp_path):
    from mcap.reader import make_reader

    from omtp_drake.errors import OmtpError
    from omtp_drake.ros import run_script

    script = tmp_path / "talker.py"
    script.write_text(SCRIPT)
    path = tmp_path / "run.mcap"
    with pytest.raises(OmtpError, match="no_such_service"):
        run_script(script, scenario="lecture6_assignment4", bag=path, calls=["/no_such_service"])
    with path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None and {c.topic for c in summary.channels.values()} >= {"/clock", "/tf_static"}
