"""A student's rclpy node for the course's gripper, belt and break beam, as they would write
it (nothing of omtp_drake imported): it reads the beam, switches gripper 1 on and off and
reads its state after each switch, powers the belt, waits for the beam to see the part the
belt carries, and stops the belt. The same requests as ros1_plugins_script.py (rospy).

    python plugins_node.py OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a generous
wall-clock bound so that a broken cell cannot hang the test.
"""

import json
import sys
import time

import rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import Bool
from std_srvs.srv import SetBool

PATIENCE = 120.0  # wall-clock seconds any one wait may take at most
QUEUE = 10  # the views' queue depth (the cell's writers keep as many)


class Student(Node):
    def __init__(self):
        super().__init__("plugins_student", parameter_overrides=[Parameter("use_sim_time", value=True)])
        self.enabled, self.attached, self.beam, self.changes = [], [], [], []
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(Bool, "/gripper1/enabled", lambda m: self.enabled.append(m.data), QUEUE)
        self.create_subscription(Bool, "/gripper1/attached", lambda m: self.attached.append(m.data), QUEUE)
        self.create_subscription(Bool, "/break_beam_sensor/object_detected", self.on_beam, latched)
        self.create_subscription(
            Bool, "/break_beam_sensor_change/object_detected", self.on_change, latched
        )
        self.gripper = self.create_client(SetBool, "/gripper1/control")
        self.conveyor = self.create_client(SetBool, "/omtp/conveyor/control")

    def on_beam(self, msg):
        self.beam.append(msg.data)

    def on_change(self, msg):
        self.changes.append(msg.data)

    def wait_for(self, what, condition):
        end = time.monotonic() + PATIENCE
        while not condition():
            if time.monotonic() > end:
                raise RuntimeError(f"no {what} within {PATIENCE} s")
            rclpy.spin_once(self, timeout_sec=0.05)

    def call(self, client, on):
        self.wait_for(client.srv_name, lambda: client.wait_for_service(timeout_sec=0.1))
        future = client.call_async(SetBool.Request(data=on))
        self.wait_for(f"{client.srv_name} answer", future.done)
        return future.result().success

    def gripper_state(self):
        """The gripper's state after the last switch: the views' last message once more have
        come than the writer's and this reader's queues hold (the first ones after the answer
        may have been written before the switch)."""
        self.enabled.clear()
        self.attached.clear()
        enough = 2 * QUEUE
        self.wait_for("gripper state", lambda: len(self.enabled) > enough and len(self.attached) > enough)
        return {"enabled": self.enabled[-1], "attached": self.attached[-1]}


def main(out):
    rclpy.init()
    node = Student()
    try:
        node.wait_for("beam state", lambda: node.beam)
        seen = {"beam_before": node.beam[-1]}
        seen["gripper_on"] = {"success": node.call(node.gripper, True), **node.gripper_state()}
        seen["gripper_off"] = {"success": node.call(node.gripper, False), **node.gripper_state()}
        seen["conveyor_on"] = node.call(node.conveyor, True)
        node.wait_for("beam change", lambda: node.changes)
        # The first change: the beam sees the part (the cell runs on without waiting for this
        # node, so the part may have passed the beam, a second change, by the time it looks).
        seen["beam_changes"] = node.changes[:1]
        seen["conveyor_off"] = node.call(node.conveyor, False)
        types = dict(node.get_topic_names_and_types())
        seen["types"] = {
            name: types.get(name, [])
            for name in ("/gripper1/state", "/break_beam_sensor", "/break_beam_sensor_change")
        }
    finally:
        node.destroy_node()
        rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(sys.argv[1])
