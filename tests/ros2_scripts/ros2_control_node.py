"""A student's rclpy node for a ros2_control robot, as they would write it (nothing of
omtp_drake imported): it waits for /joint_states, sends a JointTrajectory to
/arm_controller/joint_trajectory and watches the joints for 3 s of simulated time. Given a
second file it also watches the trajectory controller's /arm_controller/controller_state
(control_msgs on PYTHONPATH) until 3 s after its reference starts moving.

    python ros2_control_node.py OUT.json [STATE_OUT.json]

Writes what it saw to OUT.json (and the controller's states to STATE_OUT.json); the test
judges it. Every wait has a generous wall-clock bound so that a broken cell cannot hang the test.
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
    def __init__(self, watch_controller):
        super().__init__("student", parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.states = []
        self.controller_states = []
        self.create_subscription(JointState, "/joint_states", self.on_state, 10000)
        if watch_controller:
            from control_msgs.msg import JointTrajectoryControllerState

            self.create_subscription(
                JointTrajectoryControllerState, "/arm_controller/controller_state", self.on_controller, 10
            )
        self.arm = self.create_publisher(JointTrajectory, "/arm_controller/joint_trajectory", 10)

    def on_state(self, msg):
        if "shoulder_joint" in msg.name:
            self.states.append((seconds(msg.header.stamp), list(msg.name), list(msg.position)))

    def on_controller(self, msg):
        self.controller_states.append(
            {
                "stamp": seconds(msg.header.stamp),
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


def main(out, state_out=None):
    rclpy.init()
    node = Student(watch_controller=state_out is not None)
    try:
        node.wait_for("joint states", lambda: node.states)
        if state_out is not None:
            node.wait_for("controller state", lambda: node.controller_states)
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
        before_state = node.controller_states[-1] if state_out is not None else None
        node.arm.publish(msg)

        def moved():
            return [s for s in node.states if abs(s[2][0] - before[2][0]) > 1e-3]

        def reference_moved():
            return [
                s
                for s in node.controller_states
                if max(abs(a - b) for a, b in zip(s["reference"], before_state["reference"])) > 1e-6
            ]

        node.wait_for("the joints to move", moved)
        start = moved()[0][0]
        node.wait_for("3 s of joint states", lambda: node.states[-1][0] > start + 3.0)
        seen = {"before": before, "start": start, "states": node.states}
        if state_out is not None:
            node.wait_for("the reference to move", reference_moved)
            state_start = reference_moved()[0]["stamp"]
            node.wait_for("3 s of states", lambda: node.controller_states[-1]["stamp"] > state_start + 3.0)
            states = {"before": before_state, "start": state_start, "states": node.controller_states}
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)
    if state_out is not None:
        with open(state_out, "w") as f:
            json.dump(states, f)


if __name__ == "__main__":
    main(*sys.argv[1:])
