"""A student's plain rclpy node (nothing of omtp_drake imported): waits for a
/joint_states message, and writes the names and positions it carries to OUT.json.

    python joint_names_node.py OUT.json
"""

import json
import sys

import rclpy
from sensor_msgs.msg import JointState


def main() -> None:
    rclpy.init()
    node = rclpy.create_node("joint_names_listener")
    seen = {}

    def on_joints(msg: JointState) -> None:
        if msg.name and not seen:
            seen.update(names=list(msg.name), positions=list(msg.position), stamp=msg.header.stamp.sec)

    node.create_subscription(JointState, "/joint_states", on_joints, 10)
    while not seen:
        rclpy.spin_once(node, timeout_sec=0.5)
    with open(sys.argv[1], "w") as out:
        json.dump(seen, out)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
