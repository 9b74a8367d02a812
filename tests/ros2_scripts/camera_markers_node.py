"""A plain rclpy node (nothing of omtp_drake imported) that reads the rviz2 markers of the
logical cameras given until each has sent one message (or a generous wall-clock bound).

    python camera_markers_node.py OUT.json CAMERA[:TOPIC] [CAMERA[:TOPIC] ...]

(TOPIC: the camera plugin's topic where it is not the course's ``/omtp/CAMERA``.)

Writes ``{camera: [the labels of its first message]}`` to OUT.json; the test judges it.
"""

import json
import sys
import time

import rclpy
from rclpy.node import Node
from visualization_msgs.msg import Marker, MarkerArray

PATIENCE = 120.0  # wall-clock seconds to wait


def main(out, cameras):
    rclpy.init()
    node = Node("camera_markers")
    seen = {}

    def reader(camera):
        def on_markers(msg):
            if camera not in seen:
                seen[camera] = [m.text for m in msg.markers if m.type == Marker.TEXT_VIEW_FACING]

        return on_markers

    topics = dict(arg.partition(":")[::2] for arg in cameras)
    cameras = list(topics)
    for camera, topic in topics.items():
        node.create_subscription(MarkerArray, f"{topic or '/omtp/' + camera}/markers", reader(camera), 10)
    try:
        end = time.monotonic() + PATIENCE
        while set(seen) != set(cameras) and time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.1)
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
