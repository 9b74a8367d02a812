"""``/tf``, ``/tf_static`` and ``/gazebo/model_states`` of the cell over ROS 2, written by
Cyclone DDS (rclpy has no ``tf2_msgs`` nor ``gazebo_msgs``; see
:mod:`omtp_drake.ros2.dds_types`).

=============================  ============================  ====================================
topic                          type                          when
=============================  ============================  ====================================
``/tf_static``                 ``tf2_msgs/TFMessage``        once, at the start (transient local)
``/tf``                        ``tf2_msgs/TFMessage``        joint state rate (50 Hz)
``/gazebo/model_states``       ``gazebo_msgs/ModelStates``   joint state rate (50 Hz)
=============================  ============================  ====================================

Which frames go where, and their stamps, is :mod:`omtp_drake.sim.tf_broadcast`'s
(robot_state_publisher's rules, and the logical cameras' detected models).
``/gazebo/model_states`` is the ground truth of every model in the world (its name, pose
and twist in ``world``), as gazebo_ros's state plugin publishes it at its update rate.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.ros.gazebo.models import GazeboModels
from omtp_drake.ros2 import cdr
from omtp_drake.ros2.dds_types import ROS_TYPES, CycloneParticipant, ModelStates_, TFMessage_, write_cdr
from omtp_drake.sim.tf_broadcast import TfBroadcast, TfEdge

TF_MESSAGE = ROS_TYPES[TFMessage_]
MODEL_STATES = ROS_TYPES[ModelStates_]

if TYPE_CHECKING:
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.network import Ros2Network
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
    """The topics above for ``cell`` on ``network``; with ``bag``, each message into it too."""

    def __init__(self, cell: Cell, network: Ros2Network, bag: Optional[Ros2Bag] = None):
        self._cell = cell
        self._broadcast = TfBroadcast(cell.station.plant, cell.tf)
        self._models = GazeboModels(cell)
        self._bag = bag
        if bag is not None:
            from omtp_drake.ros.bag.definitions import concatenated, installed_text

            for name in (TF_MESSAGE, MODEL_STATES):
                bag.add_type(name, concatenated(name, installed_text))
        dds = CycloneParticipant(network)
        self._dds: Optional[CycloneParticipant] = dds
        self._static = dds.writer("/tf_static", TFMessage_, latched=True, depth=1)
        self._tf = dds.writer("/tf", TFMessage_)
        self._model_states = dds.writer("/gazebo/model_states", ModelStates_, depth=10)
        self._write(
            "/tf_static", self._static, tf_message(self._broadcast.static(cell.runtime.context)), TF_MESSAGE
        )

    def _write(
        self, topic: str, writer: Any, data: bytes, type_name: str, stamp_s: Optional[float] = None
    ) -> None:
        write_cdr(writer, data)
        if self._bag is not None:
            self._bag.write_cdr(topic, type_name, data, self._cell.time, stamp_s)

    def __call__(self, t: float) -> None:
        """``/tf`` and ``/gazebo/model_states`` at ``t`` (the joint state rate's caller)."""
        edges = self._broadcast.moving(self._cell.runtime.context) + self._broadcast.detected()
        self._write("/tf", self._tf, tf_message(edges), TF_MESSAGE, t)
        names, poses, twists = [], [], []
        for name, body in self._models.models():
            X, v, w = self._models.relative(body, None)
            p, q = X.translation(), X.rotation().ToQuaternion()
            names.append(name)
            poses.append((p[0], p[1], p[2], q.x(), q.y(), q.z(), q.w()))
            twists.append((v[0], v[1], v[2], w[0], w[1], w[2]))
        self._write(
            "/gazebo/model_states",
            self._model_states,
            cdr.model_states(names, poses, twists),
            MODEL_STATES,
            t,
        )

    def close(self) -> None:
        """Leaves the DDS graph: Cyclone deletes the writers and the participant with their last
        reference (the node's Ros2Cell closes this)."""
        self._static = self._tf = self._model_states = None
        self._dds = None
