"""Whether the node builds a message at all: the one rule of every topic it publishes.

A message of a volatile topic goes out only while someone would receive it: a subscription
matched to the publisher (another node's: the cell's own node subscribes to none of its
topics), or the run's bag (``--bag``, which records every topic, as ``ros2 bag record -a``
subscribes to every topic). Nobody can tell the difference: DDS delivers a volatile sample
to the readers matched when it is written, and to no one else. So while nobody listens the
node converts and sends nothing, as gazebo_ros's plugins skip what has no subscriber (ROS 1's
cameras and model states, ROS 2's ``gazebo_ros_p3d``). The plugins' own schedules still run
(their publications are polled, so rates and stamps do not shift when a subscriber comes),
except a ``lazy`` one's (the cameras: rendering is the plugin's cost, skipped as Gazebo's
camera plugins skip it). A latched (transient local) topic goes out regardless: a late reader
gets its last message.
"""

from __future__ import annotations

from typing import Any


def heard(publisher: Any) -> bool:
    """Whether a message ``publisher`` (rclpy's, or the bag's wrapper of one) published now would
    reach anyone (see the module doc)."""
    return getattr(publisher, "recorded", False) or publisher.get_subscription_count() > 0


def dds_heard(writer: Any, bag: Any) -> bool:
    """The same for a Cyclone DDS ``writer`` (:mod:`omtp_drake.ros2.dds_types`) whose messages go
    into ``bag`` too (None: no bag)."""
    return bag is not None or bool(writer.get_matched_subscriptions())
