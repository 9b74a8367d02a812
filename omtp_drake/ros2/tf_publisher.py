"""``/tf`` and ``/tf_static`` of the cell over ROS 2, as robot_state_publisher publishes them:
``tf2_msgs`` is built here for rclpy, else written by Cyclone DDS (no PyPI wheel has it; the
route is :mod:`omtp_drake.ros2.packed_topics`').

=============================  ============================  ====================================
topic                          type                          when
=============================  ============================  ====================================
``/tf_static``                 ``tf2_msgs/TFMessage``        once, at the start (transient local)
``/tf``                        ``tf2_msgs/TFMessage``        joint state rate (50 Hz), while heard
=============================  ============================  ====================================

Which frames go where, and their stamps, is :mod:`omtp_drake.sim.tf_broadcast`'s
(robot_state_publisher's rules, and the logical cameras' detected models).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from omtp_drake.ros.bag.definitions import TF_MESSAGE
from omtp_drake.ros2 import cdr
from omtp_drake.ros2.packed_topics import PackedTopics
from omtp_drake.sim.tf_broadcast import TfBroadcast, TfEdge

if TYPE_CHECKING:
    from omtp_drake.script import Cell


def _numbers(edge: TfEdge) -> tuple[float, ...]:
    """(stamp sec, nanosec, x, y, z, qx, qy, qz, qw) of an edge."""
    ns = int(round(edge.time * 1e9))
    p, q = edge.X_PC.translation(), edge.X_PC.rotation().ToQuaternion()
    return (ns // 1_000_000_000, ns % 1_000_000_000, p[0], p[1], p[2], q.x(), q.y(), q.z(), q.w())


def tf_message(edges: list[TfEdge]) -> bytes:
    """The edges as one ``tf2_msgs/TFMessage`` (XCDR1 bytes)."""
    return cdr.tf_message([(e.parent, e.child) for e in edges], [_numbers(e) for e in edges])


class TfTopics:
    """The topics above for ``cell``, by ``topics``' route (tf2_ros's QoS: ``/tf_static`` depth 1,
    ``/tf`` depth 100)."""

    def __init__(self, cell: Cell, topics: PackedTopics):
        self._cell = cell
        self._broadcast = TfBroadcast(cell.station.plant, cell.tf)
        self._static = topics.topic("/tf_static", TF_MESSAGE, latched=True, depth=1)
        self._tf = topics.topic("/tf", TF_MESSAGE)
        self._static.write(tf_message(self._broadcast.static(cell.runtime.context)), cell.time)

    def __call__(self, t: float) -> None:
        """``/tf`` at ``t`` (the joint state rate's caller), if anyone would get it."""
        if not self._tf.wanted():
            return
        edges = self._broadcast.moving(self._cell.runtime.context) + self._broadcast.detected()
        self._tf.write(tf_message(edges), self._cell.time, t)

    def close(self) -> None:
        """Leaves the DDS graph (the node's Ros2Cell closes this)."""
        self._static.close()
        self._tf.close()
