"""A student's rclpy action client of a ros2_control trajectory controller, as they would
write it (nothing of omtp_drake imported; control_msgs on PYTHONPATH): a FollowJointTrajectory
goal with unknown joints (rejected), then a good one to /arm_controller/follow_joint_trajectory,
its feedback counted, its result awaited, and the joints read on /joint_states after it.

    python follow_joint_trajectory_node.py OUT.json
"""

import json
import sys
import time

import rclpy
from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from rclpy.action import ActionClient
from rclpy.node import Node
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

PATIENCE = 120.0  # wall-clock seconds any one wait may take at most


class Student(Node):
    def __init__(self):
        super().__init__("student_action")
        self.states = []
        self.create_subscription(JointState, "/joint_states", self.on_state, 100)
        self.arm = ActionClient(self, FollowJointTrajectory, "/arm_controller/follow_joint_trajectory")

    def on_state(self, msg):
        stamp = msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec
        self.states.append((stamp, dict(zip(msg.name, msg.position))))

    def wait(self, future):
        end = time.monotonic() + PATIENCE
        while not future.done():
            if time.monotonic() > end:
                raise RuntimeError("no answer within the patience")
            rclpy.spin_once(self, timeout_sec=0.05)
        return future.result()


def main(out):
    rclpy.init()
    node = Student()
    seen = {}
    try:
        if not node.arm.wait_for_server(timeout_sec=PATIENCE):
            raise RuntimeError("no action server")
        bad = FollowJointTrajectory.Goal()
        bad.trajectory.joint_names = ["elbow_joint"]
        bad.trajectory.points = [JointTrajectoryPoint(positions=[0.2], time_from_start=Duration(sec=1))]
        seen["bad_accepted"] = node.wait(node.arm.send_goal_async(bad)).accepted

        goal = FollowJointTrajectory.Goal()
        goal.trajectory.joint_names = ["slide_joint", "shoulder_joint"]
        goal.trajectory.points = [
            JointTrajectoryPoint(positions=[0.15, -0.5], time_from_start=Duration(sec=1)),
            JointTrajectoryPoint(
                positions=[0.1, 0.8], velocities=[0.0, 0.0], time_from_start=Duration(sec=2)
            ),
        ]
        feedback = []
        handle = node.wait(
            node.arm.send_goal_async(goal, feedback_callback=lambda m: feedback.append(m.feedback))
        )
        seen["accepted"] = handle.accepted
        result = node.wait(handle.get_result_async())
        seen["status"] = result.status
        seen["error_code"] = result.result.error_code
        seen["feedback"] = len(feedback)
        seen["feedback_stamps"] = [f.header.stamp.sec + 1e-9 * f.header.stamp.nanosec for f in feedback]
        seen["feedback_joints"] = list(feedback[-1].joint_names) if feedback else []
        # The joints after the goal: a state stamped after its 2 s trajectory's end (counted from
        # the first feedback, at the goal's start; the subscription's queue may still hold older
        # states when the result comes, and a busy client may have lost the last feedback).
        done = seen["feedback_stamps"][0] + 2.0 if feedback else 0.0
        end = time.monotonic() + PATIENCE
        while not any(t > done + 0.1 for t, _ in node.states) and time.monotonic() < end:
            rclpy.spin_once(node, timeout_sec=0.05)
        seen["after"] = next(state for t, state in node.states if t > done + 0.1)
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
