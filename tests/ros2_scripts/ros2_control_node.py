"""A student's rclpy node for a ros2_control robot, as they would write it (nothing of
omtp_drake imported): it waits for /joint_states, sends a JointTrajectory to
/arm_controller/joint_trajectory and watches the joints for 3 s of simulated time.

    python ros2_control_node.py OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a generous
wall-clock bound so that a broken cell cannot hang the test.
"""

import json
import sys
import time

import rclpy
from builtin_interfaces.msg import Duration
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

JOINTS = ["shoulder_joint", "slide_joint"]
PATIENCE = 120.0  # wall-clock seconds any one wait may take at most


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


class Student(Node):
    def __init__(self):
        super().__init__("student", parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.states = []
        self.create_subscription(JointState, "/joint_states", self.on_state, 10000)
        self.arm = self.create_publisher(JointTrajectory, "/arm_controller/joint_trajectory", 10)

    def on_state(self, msg):
        if "shoulder_joint" in msg.name:
            self.states.append((seconds(msg.header.stamp), list(msg.name), list(msg.position)))

    def wait_for(self, what, condition):
        end = time.monotonic() + PATIENCE
        while not condition():
            if time.monotonic() > end:
                raise RuntimeError(f"no {what} within {PATIENCE} s")
            rclpy.spin_once(self, timeout_sec=0.05)


def main(out):
    rclpy.init()
    node = Student()
    try:
        node.wait_for("joint states", lambda: node.states)
        node.wait_for("the controller", lambda: node.arm.get_subscription_count() > 0)
        msg = JointTrajectory()
        msg.joint_names = ["slide_joint", "shoulder_joint"]
        msg.points = [
            JointTrajectoryPoint(positions=[0.15, -0.5], time_from_start=Duration(sec=1)),
            JointTrajectoryPoint(
                positions=[0.1, 0.8], velocities=[0.0, 0.0], time_from_start=Duration(sec=2)
            ),
        ]
        before = node.states[-1]
        node.arm.publish(msg)

        def moved():
            return [s for s in node.states if abs(s[2][0] - before[2][0]) > 1e-3]

        node.wait_for("the joints to move", moved)
        start = moved()[0][0]
        node.wait_for("3 s of joint states", lambda: node.states[-1][0] > start + 3.0)
        seen = {"before": before, "start": start, "states": node.states}
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
