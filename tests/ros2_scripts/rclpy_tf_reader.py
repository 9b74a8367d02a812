"""A student's plain rclpy node reading the cell's /tf_static, /tf and /gazebo/model_states
with the real tf2_msgs and gazebo_msgs types (on PYTHONPATH; nothing of omtp_drake imported):
the cell writes these topics through Cyclone DDS, this node reads them through Fast DDS.

    python rclpy_tf_reader.py OUT.json
"""

import json
import sys
import time

import rclpy
from gazebo_msgs.msg import ModelStates
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

PATIENCE = 120.0


def main(out):
    rclpy.init()
    node = rclpy.create_node("rclpy_tf_reader")
    seen = {"static": {}, "tf": [], "models": []}

    def on_static(msg):
        for t in msg.transforms:
            p = t.transform.translation
            seen["static"][t.child_frame_id] = [t.header.frame_id, p.x, p.y, p.z]

    latched = QoSProfile(
        depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
    )
    node.create_subscription(TFMessage, "/tf_static", on_static, latched)
    moving = set()

    def on_tf(msg):
        seen["tf"].append(len(msg.transforms))
        moving.update(t.child_frame_id for t in msg.transforms)

    node.create_subscription(TFMessage, "/tf", on_tf, 100)
    on_models = lambda m: seen["models"].append(list(m.name))  # noqa: E731
    node.create_subscription(ModelStates, "/gazebo/model_states", on_models, 10)
    end = time.monotonic() + PATIENCE
    while time.monotonic() < end and not (seen["static"] and len(seen["tf"]) >= 5 and seen["models"]):
        rclpy.spin_once(node, timeout_sec=0.05)
    seen["models"] = seen["models"][-1] if seen["models"] else []
    seen["tf_frames"] = sorted(moving)
    node.destroy_node()
    rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
