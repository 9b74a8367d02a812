"""What the ROS 2 node does while nobody listens (omtp_drake/ros2/audience.py): no message of a
volatile topic is built or sent, only the latched ones go out; the node's clock reads the
simulated time without subscribing to its own /clock; and when a subscriber comes, the
plugins' messages keep their schedule (the joint states on their 50 Hz grid from t = 0).
In-process (a peer node in a second rclpy context), loopback, a domain of its own.
"""

from __future__ import annotations

import time
from collections import Counter

import pytest
from test_ros2 import PATIENCE, _dds_files, _leaked_dds_files, needs_ros2, network

__all__ = ["network"]  # test_ros2's fixture, used by name


def _count_publishes(node) -> Counter:
    sent: Counter = Counter()
    for publisher in node.publishers:
        publish = publisher.publish

        def counted(msg, publish=publish, topic=publisher.topic_name):
            sent[topic] += 1
            publish(msg)

        publisher.publish = counted
    return sent


@needs_ros2
def test_nobody_listening_nothing_is_sent_and_a_late_subscriber_gets_the_plugins_schedule(network):
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy
    from sensor_msgs.msg import JointState

    from omtp_drake.ros2.bridge import Ros2Cell
    from omtp_drake.script import Cell

    shm_before = _dds_files()
    with Cell("lecture6_assignment1") as cell, Ros2Cell(cell, network) as node:
        sent = _count_publishes(node.node)
        for _ in range(32):
            node.step()
        latched = {
            p.topic_name
            for p in node.node.publishers
            if p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
        }
        assert sent and set(sent) <= latched, sent  # the break beam's latched views only
        assert node.node.get_clock().now().nanoseconds == round(cell.time * 1e9)
        published = {p.topic_name for p in node.node.publishers}
        assert not published & {s.topic_name for s in node.node.subscriptions}

        context = rclpy.Context()
        rclpy.init(context=context, domain_id=network.domain_id)
        try:
            peer = rclpy.create_node("peer", context=context)
            stamps: list[float] = []
            on_joints = lambda m: stamps.append(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9)  # noqa: E731
            subscription = peer.create_subscription(JointState, "/joint_states", on_joints, 100)
            (joint_states,) = [p for p in node.node.publishers if p.topic_name == "/joint_states"]
            deadline = time.monotonic() + PATIENCE
            # Matched on both sides (a reader drops what a writer it has not discovered sends).
            while time.monotonic() < deadline and not (
                joint_states.get_subscription_count() and subscription.get_publisher_count()
            ):
                time.sleep(0.01)
            # Heard from t = 0.33 on: a schedule restarted there would stamp 0.33, 0.35...
            for _ in range(20):
                node.step()
            executor = SingleThreadedExecutor(context=context)
            executor.add_node(peer)
            while len(stamps) < 10 and time.monotonic() < deadline:
                executor.spin_once(timeout_sec=0.05)
            executor.shutdown()
            peer.destroy_node()
        finally:
            context.try_shutdown()
    assert sent["/joint_states"] == len(stamps) == 10, (sent, stamps)
    assert stamps == pytest.approx([0.34 + 0.02 * i for i in range(10)], abs=1e-9)
    assert not _leaked_dds_files(shm_before, network.domain_id), "Fast DDS left shared memory behind"
