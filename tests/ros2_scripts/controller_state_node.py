"""A student's rclpy node watching a ros2_control trajectory controller's state, as they would
write it (nothing of omtp_drake imported; control_msgs on PYTHONPATH): it subscribes
/arm_controller/controller_state, sends a JointTrajectory to /arm_controller/joint_trajectory
and keeps every state it receives until 3 s of simulated time after its reference starts moving.

    python controller_state_node.py OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a generous wall-clock bound
so that a broken cell cannot hang the test.
"""

import json
import sys
import time

import rclpy
from builtin_interfaces.msg import Duration
from control_msgs.msg import JointTrajectoryControllerState
from rclpy.node import Node
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

PATIENCE = 120.0  # wall-clock seconds any one wait may take at most


class Student(Node):
    def __init__(self):
        super().__init__("student_state")
        self.states = []
        self.create_subscription(
            JointTrajectoryControllerState, "/arm_controller/controller_state", self.on_state, 10
        )
        self.arm = self.create_publisher(JointTrajectory, "/arm_controller/joint_trajectory", 10)

    def on_state(self, msg):
        self.states.append(
            {
                "stamp": msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec,
                "joint_names": list(msg.joint_names),
                "reference": list(msg.reference.positions),
                "feedback": list(msg.feedback.positions),
                "error": list(msg.error.positions),
                "output": list(msg.output.positions),
                "speed_scaling_factor": msg.speed_scaling_factor,
            }
        )

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
        node.wait_for("controller state", lambda: node.states)
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
            return [
                s
                for s in node.states
                if max(abs(a - b) for a, b in zip(s["reference"], before["reference"])) > 1e-6
            ]

        node.wait_for("the reference to move", moved)
        start = moved()[0]["stamp"]
        node.wait_for("3 s of states", lambda: node.states[-1]["stamp"] > start + 3.0)
        seen = {"before": before, "start": start, "states": node.states}
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
