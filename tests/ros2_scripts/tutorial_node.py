"""A student's rclpy node for the URDF tutorial's robot (slider + arm + depth camera),
as they would write it (nothing of omtp_drake imported): it sends one trajectory on
/set_joint_trajectory, watches /joint_states, and looks at the depth camera's topics.

    python tutorial_node.py OUT.json LEAD SPAN

Once it hears the cell (/clock, a /joint_states message, each camera topic, a subscriber
of /set_joint_trajectory), it sends tests/ros2_scripts/trajectory.json's trajectory, its header
stamped START: the first whole half second at least LEAD simulated seconds after the
/clock it heard last (so START does not depend on how long DDS discovery took). The node
records every /joint_states message until /clock, and then /joint_states, reach
END = START + SPAN. Before it sends, it takes one message of each camera topic and
unsubscribes (the camera renders only while someone listens), so that a 640 x 480 cloud
stream is not what the joint states of the recorded span queue behind. Writes what it saw,
START and END to OUT.json; every wait has a wall-clock bound.
"""

import json
import math
import sys
import time
from pathlib import Path

import rclpy
from builtin_interfaces.msg import Duration, Time
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, JointState, PointCloud2
from std_msgs.msg import String
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

PATIENCE = 120.0  # wall-clock seconds any one wait may take at most
CAMERA = {
    "/tip_camera/image_raw": Image,
    "/tip_camera/depth/image_raw": Image,
    "/tip_camera/camera_info": CameraInfo,
    "/tip_camera/points": PointCloud2,
}


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


def as_time(t):
    return Time(sec=int(t), nanosec=int(round((t % 1) * 1e9)))


def trajectory_msg(start):
    spec = json.loads((Path(__file__).parent / "trajectory.json").read_text())
    msg = JointTrajectory()
    msg.header.frame_id = spec["frame_id"]
    msg.header.stamp = as_time(start)
    msg.joint_names = spec["joint_names"]
    for positions, after in spec["points"]:
        d = as_time(after)
        msg.points.append(
            JointTrajectoryPoint(positions=positions, time_from_start=Duration(sec=d.sec, nanosec=d.nanosec))
        )
    return msg


class TutorialNode(Node):
    def __init__(self):
        super().__init__("tutorial_student", parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.clock = -1.0
        self.states = []
        self.camera = {}
        self.create_subscription(Clock, "/clock", self.on_clock, 10)
        self.create_subscription(JointState, "/joint_states", self.states.append, 200)
        self.camera_subs = [
            self.create_subscription(kind, name, lambda m, name=name: self.camera.setdefault(name, m), 2)
            for name, kind in CAMERA.items()
        ]
        self.trajectory = self.create_publisher(JointTrajectory, "/set_joint_trajectory", 1)
        self.descriptions = []
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(
            String, "/robot_description", lambda m: self.descriptions.append(m.data), latched
        )

    def on_clock(self, msg):
        self.clock = seconds(msg.clock)

    def wait_for(self, what, condition):
        end = time.monotonic() + PATIENCE
        while not condition():
            if time.monotonic() > end:
                raise RuntimeError(f"no {what} within {PATIENCE} s")
            rclpy.spin_once(self, timeout_sec=0.05)


def describe(name, msg):
    out = {"stamp": seconds(msg.header.stamp), "frame_id": msg.header.frame_id}
    out["size"] = [msg.width, msg.height]
    if isinstance(msg, Image):
        out["encoding"] = msg.encoding
        out["bytes"] = len(msg.data)
    elif isinstance(msg, PointCloud2):
        out["fields"] = [[f.name, f.offset] for f in msg.fields]
        out["point_step"] = msg.point_step
        out["bytes"] = len(msg.data)
    else:
        out["k"] = list(msg.k)
    return out


def main(out, lead, span):
    rclpy.init()
    node = TutorialNode()
    try:
        node.wait_for("clock", lambda: node.clock >= 0.0)
        node.wait_for("/joint_states", lambda: node.states)
        node.wait_for("camera topics", lambda: len(node.camera) == len(CAMERA))
        for sub in node.camera_subs:
            node.destroy_subscription(sub)
        node.wait_for("the trajectory's subscriber", lambda: node.trajectory.get_subscription_count() > 0)
        sent_at = node.clock
        start = math.ceil((sent_at + lead) * 2.0) / 2.0
        end = start + span
        node.trajectory.publish(trajectory_msg(start))
        node.wait_for(f"/clock at {end}", lambda: node.clock >= end)
        node.wait_for(f"/joint_states at {end}", lambda: seconds(node.states[-1].header.stamp) >= end)
        node.wait_for("/robot_description", lambda: node.descriptions)
        seen = {
            "start": start,
            "end": end,
            "sent_at": sent_at,
            "states": [[seconds(m.header.stamp), list(m.name), list(m.position)] for m in node.states],
            "camera": {name: describe(name, msg) for name, msg in node.camera.items()},
            "description": node.descriptions[0],
        }
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]), float(sys.argv[3]))
