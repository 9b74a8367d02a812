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

from pydrake.math import RigidTransform

from omtp_drake.ros.gazebo.models import GazeboModels
from omtp_drake.ros2.dds_types import (
    ROS_TYPES,
    CycloneParticipant,
    Header_,
    ModelStates_,
    Point_,
    Pose_,
    Quaternion_,
    TFMessage_,
    Time_,
    Transform_,
    TransformStamped_,
    Twist_,
    Vector3_,
)
from omtp_drake.sim.tf_broadcast import TfBroadcast, TfEdge

if TYPE_CHECKING:
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.network import Ros2Network
    from omtp_drake.script import Cell


def stamp(t: float) -> Time_:
    sec = int(t // 1)
    return Time_(sec, int(round((t - sec) * 1e9)))


def _quaternion(X: RigidTransform) -> Quaternion_:
    q = X.rotation().ToQuaternion()
    return Quaternion_(q.x(), q.y(), q.z(), q.w())


def tf_message(edges: list[TfEdge]) -> TFMessage_:
    """The edges as one ``tf2_msgs/TFMessage``."""
    return TFMessage_(
        [
            TransformStamped_(
                Header_(stamp(e.time), e.parent),
                e.child,
                Transform_(Vector3_(*map(float, e.X_PC.translation())), _quaternion(e.X_PC)),
            )
            for e in edges
        ]
    )


def pose(X: RigidTransform) -> Pose_:
    return Pose_(Point_(*map(float, X.translation())), _quaternion(X))


class TfTopics:
    """The topics above for ``cell`` on ``network``; with ``bag``, each message into it too."""

    def __init__(self, cell: Cell, network: Ros2Network, bag: Optional[Ros2Bag] = None):
        self._cell = cell
        self._broadcast = TfBroadcast(cell.station.plant, cell.tf)
        self._models = GazeboModels(cell)
        self._bag = bag
        if bag is not None:
            from omtp_drake.ros.bag.definitions import concatenated, installed_text

            for mirror in (TFMessage_, ModelStates_):
                bag.add_type(ROS_TYPES[mirror], concatenated(ROS_TYPES[mirror], installed_text))
        self._dds = CycloneParticipant(network)
        self._static = self._dds.writer("/tf_static", TFMessage_, latched=True, depth=1)
        self._tf = self._dds.writer("/tf", TFMessage_)
        self._model_states = self._dds.writer("/gazebo/model_states", ModelStates_, depth=10)
        self._write("/tf_static", self._static, tf_message(self._broadcast.static(cell.runtime.context)))

    def _write(self, topic: str, writer: Any, message: Any, stamp_s: Optional[float] = None) -> None:
        writer.write(message)
        if self._bag is not None:
            data = message.serialize(use_version_2=False)
            self._bag.write_cdr(topic, ROS_TYPES[type(message)], data, self._cell.time, stamp_s)

    def __call__(self, t: float) -> None:
        """``/tf`` and ``/gazebo/model_states`` at ``t`` (the joint state rate's caller)."""
        edges = self._broadcast.moving(self._cell.runtime.context) + self._broadcast.detected()
        self._write("/tf", self._tf, tf_message(edges), t)
        names, poses, twists = [], [], []
        for name, body in self._models.models():
            X, v, w = self._models.relative(body, None)
            names.append(name)
            poses.append(pose(X))
            twists.append(Twist_(Vector3_(*map(float, v)), Vector3_(*map(float, w))))
        self._write("/gazebo/model_states", self._model_states, ModelStates_(names, poses, twists), t)
