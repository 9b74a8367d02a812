"""A peer of the cell on ROS 2: starts the course's spawner (std_srvs/Empty, the course's
type) and watches the parts appear in /gazebo/model_states and /gazebo/link_states, read
with raw Cyclone DDS readers (no PyPI wheel has gazebo_msgs for rclpy); rclpy for the rest.

    python spawner_node.py DOMAIN OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a wall-clock bound.
"""

import json
import sys
import time

import rclpy
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration
from rclpy.qos import DurabilityPolicy, QoSProfile
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header
from std_srvs.srv import Empty

from omtp_drake.ros2.dds_types import LinkStates_, ModelStates_, cyclone_config
from omtp_drake.ros2.network import Ros2Network

PATIENCE = 120.0


def reader(participant, topic, mirror):
    qos = Qos(
        Policy.Reliability.Reliable(duration(seconds=1)),
        # Every sample kept until taken: on a busy machine this loop can fall seconds behind the
        # free-running cell, and a bounded history would drop the sample where the part appears.
        Policy.History.KeepAll,
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )
    return DataReader(participant, Topic(participant, topic, mirror), qos=qos)


def call(node, client, deadline):
    assert client.wait_for_service(timeout_sec=PATIENCE), client.srv_name
    future = client.call_async(Empty.Request())
    while not future.done() and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
    assert future.done(), client.srv_name


def main(domain, out):
    dds_domain = Domain(domain, cyclone_config(Ros2Network(domain)))  # noqa: F841 (kept alive)
    participant = DomainParticipant(domain)
    models = reader(participant, "rt/gazebo/model_states", ModelStates_)
    links = reader(participant, "rt/gazebo/link_states", LinkStates_)

    rclpy.init(domain_id=domain)
    node = rclpy.create_node("spawner_peer")
    seen = {"clock": None, "spawned": None, "models": None, "links": None, "before": None}
    node.create_subscription(
        Clock, "/clock", lambda m: seen.update(clock=m.clock.sec + m.clock.nanosec * 1e-9), 10
    )
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def on_spawned(msg):
        seen["spawned"] = {"stamp": msg.stamp.sec + msg.stamp.nanosec * 1e-9, "frame_id": msg.frame_id}

    node.create_subscription(Header, "/spawned_part", on_spawned, latched)
    deadline = time.monotonic() + PATIENCE
    while (seen["clock"] is None or seen["before"] is None) and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
        for msg in models.take(100):
            seen["before"] = list(msg.name)
    seen["called"] = seen["clock"]
    call(node, node.create_client(Empty, "/start_spawn"), deadline)
    while time.monotonic() < deadline and not (seen["models"] and seen["links"] and seen["spawned"]):
        rclpy.spin_once(node, timeout_sec=0.05)
        for msg in models.take(100):
            if seen["models"] is None and any("object" in n for n in msg.name):
                seen["models"] = list(msg.name)
                seen["object_xyz"] = [[p.position.x, p.position.y, p.position.z] for p in msg.pose]
        for msg in links.take(100):
            if seen["links"] is None and any(n.startswith("object") for n in msg.name):
                seen["links"] = list(msg.name)
    call(node, node.create_client(Empty, "/stop_spawn"), deadline)
    node.destroy_node()
    rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2])
