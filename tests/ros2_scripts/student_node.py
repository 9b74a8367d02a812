"""A student's rclpy node for the simulated cell, as they would write it (nothing of
omtp_drake imported): it follows /clock, reads /joint_states and a camera's
/points, sets robot1's joints with /set_joint_trajectory and calls the gripper.

    python student_node.py OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a generous
wall-clock bound so that a broken cell cannot hang the test.
"""

import json
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseArray
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState, PointCloud2
from std_msgs.msg import String
from std_srvs.srv import SetBool
from visualization_msgs.msg import MarkerArray

JOINTS = [
    "robot1_shoulder_pan_joint",
    "robot1_shoulder_lift_joint",
    "robot1_elbow_joint",
    "robot1_wrist_1_joint",
    "robot1_wrist_2_joint",
    "robot1_wrist_3_joint",
]
PATIENCE = 120.0  # wall-clock seconds any one wait may take at most


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


class Student(Node):
    def __init__(self):
        super().__init__("student", parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.clocks = []
        self.joint_states = []
        self.clouds = []
        self.create_subscription(Clock, "/clock", lambda m: self.clocks.append(seconds(m.clock)), 10)
        self.create_subscription(JointState, "/joint_states", self.joint_states.append, 100)
        self.create_subscription(PointCloud2, "/logical_camera_1/points", self.clouds.append, 2)
        self.descriptions = []
        self.camera = []
        self.markers = []
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(
            String, "/robot_description", lambda m: self.descriptions.append(m.data), latched
        )
        self.create_subscription(PoseArray, "/omtp/logical_camera_1/poses", self.camera.append, 10)
        self.create_subscription(MarkerArray, "/omtp/logical_camera_1/markers", self.markers.append, 10)
        self.parts = []
        self.create_subscription(PoseArray, "/omtp/parts/poses", self.parts.append, 10)
        self.gripper = self.create_client(SetBool, "/gripper1/control")
        self.conveyor = self.create_client(SetBool, "/omtp/conveyor/control")

    def wait_for(self, what, condition):
        end = time.monotonic() + PATIENCE
        while not condition():
            if time.monotonic() > end:
                raise RuntimeError(f"no {what} within {PATIENCE} s")
            rclpy.spin_once(self, timeout_sec=0.05)

    def robot1(self, msg):
        return [msg.position[msg.name.index(j)] for j in JOINTS]

    def cloud(self):
        self.wait_for("point cloud", lambda: self.clouds)
        msg = self.clouds[-1]
        fields = {f.name: f.offset for f in msg.fields}
        raw = np.frombuffer(bytes(msg.data), dtype=np.uint8).reshape(-1, msg.point_step)
        xyz = np.stack([raw[:, fields[k] : fields[k] + 4].copy().view("<f4")[:, 0] for k in "xyz"], axis=1)
        xyz = xyz[np.isfinite(xyz).all(axis=1)]
        return {
            "frame_id": msg.header.frame_id,
            "stamp": seconds(msg.header.stamp),
            "height": msg.height,
            "width": msg.width,
            "points": xyz.tolist(),
        }

    def call(self, client, on):
        self.wait_for(client.srv_name, lambda: client.wait_for_service(timeout_sec=0.1))
        future = client.call_async(SetBool.Request(data=on))
        self.wait_for(f"{client.srv_name} answer", future.done)
        return {"success": future.result().success, "message": future.result().message}

    def logical_camera(self):
        self.wait_for("camera poses, markers, parts", lambda: self.camera and self.markers and self.parts)
        poses = self.camera[-1]
        return {
            "frame_id": poses.header.frame_id,
            "positions": [[p.position.x, p.position.y, p.position.z] for p in poses.poses],
            "labels": [m.text for m in self.markers[-1].markers if m.text],
            "parts": [[p.position.x, p.position.y, p.position.z] for p in self.parts[-1].poses],
            "parts_frame": self.parts[-1].header.frame_id,
        }


def main(out):
    rclpy.init()
    node = Student()
    try:
        node.wait_for("clock", lambda: len(node.clocks) >= 5)
        node.wait_for("joint states", lambda: node.joint_states)
        node.wait_for("robot description", lambda: node.descriptions)
        seen = {
            "clocks": node.clocks[:50],
            "now": node.get_clock().now().nanoseconds * 1e-9,
            "joints_before": node.robot1(node.joint_states[-1]),
            "cloud": node.cloud(),
            "logical_camera": node.logical_camera(),  # before the belt moves the part
            "gripper": node.call(node.gripper, True),
            "conveyor": node.call(node.conveyor, True),
            "description": node.descriptions[0] if node.descriptions else "",
        }
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
