"""The ROS 1 master's graph calls under ros-run (rospy.get_published_topics,
rosgraph.Master's getSystemState / getTopicTypes / getPublishedTopics), from a probe
written as a student writes one."""

import json
import textwrap

import pytest

from omtp_drake.ros import run_script

PROBE = """
    #!/usr/bin/env python
    # Which topics are there? (a group's probe before wiring their camera callback)
    import json, sys
    import rospy
    import rosgraph
    from std_msgs.msg import String
    from omtp_gazebo.msg import LogicalCameraImage

    def on_image(msg):
        pass

    rospy.init_node("topic_probe")
    pub = rospy.Publisher("/probe/status", String, queue_size=1)
    rospy.Subscriber("/omtp/logical_camera_1", LogicalCameraImage, on_image)
    topics = rospy.get_published_topics()
    omtp_only = rospy.get_published_topics("/omtp")
    master = rosgraph.Master("/rostopic")
    pubs, subs, srvs = master.getSystemState()
    out = {
        "topics": topics,
        "omtp": omtp_only,
        "types": master.getTopicTypes(),
        "pubs": pubs, "subs": subs, "srvs": srvs,
        "nodes": sorted({n for _, ns in pubs + subs + srvs for n in ns}),
        "online": rosgraph.is_master_online(),
    }
    pub.unregister()
    out["after"] = [t for t, _ in rospy.get_published_topics()]
    json.dump(out, open(sys.argv[1], "w"))
"""


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    folder = tmp_path_factory.mktemp("probe")
    script = folder / "topic_probe.py"
    script.write_text(textwrap.dedent(PROBE))
    out = folder / "out.json"
    report = run_script(script, [str(out)], scenario="lecture6_assignment1", timeout=5.0)
    return report, json.loads(out.read_text())


def test_get_published_topics_lists_the_cells_topics_and_the_scripts(probe):
    report, data = probe
    assert report.exception is None
    topics = dict(map(tuple, data["topics"]))
    assert topics["/omtp/logical_camera_1"] == "omtp_gazebo/LogicalCameraImage"
    assert topics["/probe/status"] == "std_msgs/String"
    assert topics["/joint_states"] == "sensor_msgs/JointState"
    # a namespace is a prefix with its trailing slash, as rosmaster filters
    assert data["omtp"] and all(t.startswith("/omtp/") for t, _ in data["omtp"])
    assert "/probe/status" not in data["after"]


def test_the_masters_system_state_names_who_publishes_subscribes_and_serves(probe):
    _, data = probe
    pubs, subs, srvs = (dict(map(tuple, rows)) for rows in (data["pubs"], data["subs"], data["srvs"]))
    assert pubs["/probe/status"] == ["/topic_probe"]
    assert pubs["/omtp/logical_camera_1"] == ["/gazebo"]
    assert "/topic_probe" in subs["/omtp/logical_camera_1"]
    assert "/gazebo/spawn_urdf_model" in srvs and "/spawn_object_once" in srvs
    assert {"/gazebo", "/topic_probe"} <= set(data["nodes"])
    types = dict(map(tuple, data["types"]))
    assert types["/omtp/logical_camera_1"] == "omtp_gazebo/LogicalCameraImage" and data["online"]
