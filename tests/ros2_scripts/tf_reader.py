"""A late reader of the cell's /tf_static and /tf: a raw DDS reader (Cyclone; no PyPI wheel
has tf2_msgs for rclpy), and an rclpy node in the same process that lists the graph's topic
types, reads /robot_description, and reads a sequence<struct> type (geometry_msgs/PoseArray)
that a Cyclone writer publishes: what a Fast DDS subscriber matches.

    python tf_reader.py DOMAIN OUT.json

Writes what it saw to OUT.json; the test judges it. Every wait has a wall-clock bound.
"""

import json
import sys
import time
from dataclasses import dataclass, field

import rclpy
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl import annotations as annotate
from cyclonedds.idl.types import sequence
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration
from geometry_msgs.msg import PoseArray
from rclpy.qos import DurabilityPolicy, QoSProfile
from std_msgs.msg import String

from omtp_drake.ros2.dds_types import (
    Header_,
    ModelStates_,
    Point_,
    Pose_,
    Quaternion_,
    TFMessage_,
    cyclone_config,
)
from omtp_drake.ros2.network import Ros2Network

PATIENCE = 120.0


@annotate.final
@dataclass
class PoseArray_(IdlStruct, typename="geometry_msgs::msg::dds_::PoseArray_"):
    header: Header_ = field(default_factory=Header_)
    poses: sequence[Pose_] = field(default_factory=list)


def qos(latched):
    durability = Policy.Durability.TransientLocal if latched else Policy.Durability.Volatile
    return Qos(
        Policy.Reliability.Reliable(duration(seconds=1)),
        durability,
        Policy.History.KeepLast(1 if latched else 100),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )


def transforms(msg):
    return [
        {
            "parent": t.header.frame_id,
            "child": t.child_frame_id,
            "stamp": t.header.stamp.sec + t.header.stamp.nanosec * 1e-9,
            "xyz": [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z],
            "xyzw": [
                t.transform.rotation.x,
                t.transform.rotation.y,
                t.transform.rotation.z,
                t.transform.rotation.w,
            ],
        }
        for t in msg.transforms
    ]


def main(domain, out):
    network = Ros2Network(domain)
    dds_domain = Domain(domain, cyclone_config(network))  # noqa: F841 (kept alive)
    participant = DomainParticipant(domain)
    static = DataReader(participant, Topic(participant, "rt/tf_static", TFMessage_), qos=qos(True))
    tf = DataReader(participant, Topic(participant, "rt/tf", TFMessage_), qos=qos(False))
    models = DataReader(
        participant, Topic(participant, "rt/gazebo/model_states", ModelStates_), qos=qos(False)
    )
    probe = DataWriter(participant, Topic(participant, "rt/omtp_probe/poses", PoseArray_), qos=qos(False))

    rclpy.init(domain_id=domain)
    node = rclpy.create_node("tf_reader")
    seen = {"static": None, "tf": [], "models": None, "description": None, "probe": None}
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node.create_subscription(String, "/robot_description", lambda m: seen.update(description=m.data), latched)

    def on_probe(msg):
        seen["probe"] = {
            "frame_id": msg.header.frame_id,
            "poses": [[p.position.x, p.orientation.w] for p in msg.poses],
        }

    node.create_subscription(PoseArray, "/omtp_probe/poses", on_probe, 10)
    sent = PoseArray_(
        Header_(frame_id="probe"), [Pose_(Point_(0.5, 0, 0), Quaternion_()), Pose_(Point_(1.5, 0, 0))]
    )
    deadline = time.monotonic() + PATIENCE
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
        for msg in static.take(10):
            seen["static"] = transforms(msg)
        for msg in tf.take(10):
            seen["tf"].append(transforms(msg))
        for msg in models.take(10):
            seen["models"] = {
                "name": list(msg.name),
                "xyz": [[p.position.x, p.position.y, p.position.z] for p in msg.pose],
            }
        if seen["probe"] is None:
            probe.write(sent)
        if (
            seen["static"]
            and len(seen["tf"]) >= 5
            and seen["models"]
            and seen["description"]
            and seen["probe"]
        ):
            break
    seen["types"] = {name: types for name, types in node.get_topic_names_and_types()}
    node.destroy_node()
    rclpy.shutdown()
    with open(out, "w") as f:
        json.dump(seen, f)


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2])
