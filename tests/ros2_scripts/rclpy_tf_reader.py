"""A student's plain rclpy node joining the cell late and reading its /tf_static, /tf,
/gazebo/model_states and /robot_description, with the real tf2_msgs and gazebo_msgs types
(on PYTHONPATH; nothing of omtp_drake imported), and the graph's view of who publishes /tf.

    python rclpy_tf_reader.py OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a wall-clock bound.
"""

import json
import sys
import time

import rclpy
from gazebo_msgs.msg import ModelStates
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

PATIENCE = 120.0


def transforms(msg):
    return [
        {
            "parent": t.header.frame_id,
            "child": t.child_frame_id,
            "stamp": t.header.stamp.sec + t.header.stamp.nanosec * 1e-9,
            "xyz": [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z],
            "xyzw": [
                t.transform.rotation.x,
                t.transform.rotation.y,
                t.transform.rotation.z,
                t.transform.rotation.w,
            ],
        }
        for t in msg.transforms
    ]


#: What rclpy's graph names a publisher whose node it does not know (yet).
UNKNOWN = "_NODE_NAME_UNKNOWN_"
#: How long the reader waits for the /tf publishers' node names (s).
NAME_PATIENCE = 3.0


def main(out):
    rclpy.init()
    node = rclpy.create_node("rclpy_tf_reader")
    seen = {"static": None, "tf": [], "models": None, "description": None}
    latched = QoSProfile(
        depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
    )
    node.create_subscription(TFMessage, "/tf_static", lambda m: seen.update(static=transforms(m)), latched)
    node.create_subscription(TFMessage, "/tf", lambda m: seen["tf"].append(transforms(m)), 100)
    node.create_subscription(String, "/robot_description", lambda m: seen.update(description=m.data), latched)

    def on_models(msg):
        seen["models"] = {
            "name": list(msg.name),
            "xyz": [[p.position.x, p.position.y, p.position.z] for p in msg.pose],
        }

    node.create_subscription(ModelStates, "/gazebo/model_states", on_models, 10)
    end = time.monotonic() + PATIENCE
    while time.monotonic() < end and not (
        seen["static"] and len(seen["tf"]) >= 5 and seen["models"] and seen["description"]
    ):
        rclpy.spin_once(node, timeout_sec=0.05)
    seen["types"] = {name: types for name, types in node.get_topic_names_and_types()}
    # A publisher's node name reaches the graph after its endpoint (ROS 2's discovery info is a
    # topic of its own): until then rclpy says _NODE_NAME_UNKNOWN_. A writer with no ROS node
    # (Cyclone DDS's) stays unknown: the wait is bounded.
    names_by = time.monotonic() + NAME_PATIENCE
    while True:
        names = sorted(i.node_name for i in node.get_publishers_info_by_topic("/tf"))
        if UNKNOWN not in names or time.monotonic() > names_by:
            break
        rclpy.spin_once(node, timeout_sec=0.05)
    seen["tf_publishers"] = names
    node.destroy_node()
    rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
