"""A ROS 1 session recorded into a ROS 2 bag (``ros-run --bag``, ``flexbe-run --bag``), as
``rosbag record -a`` would record the course's ROS graph, in ROS 2's types.

Every topic of the session goes in: the cell's (each one subscribed, as rosbag's recorder
subscribes to all: the cameras render), the script's and the nodes' publishers, Gazebo's
latched ones, each message at the simulated time it was published (its stamp: the header's)
and converted by :mod:`omtp_drake.ros.bag.ros1`. Besides them, what ROS would have on the
graph though the in-process session needs no topic for it:

- ``/clock`` (``rosgraph_msgs/Clock``) at :data:`CLOCK_RATE_HZ`;
- ``/tf_static`` once at the start and ``/tf`` at the joint state rate, by the rules of
  :mod:`omtp_drake.sim.tf_broadcast` (what robot_state_publisher and the logical cameras send).

Left out: ``/gazebo/model_states`` and ``/gazebo/link_states``, which Gazebo publishes at every
physics step (``rosbag record -a -x``'s usual exclusion; the bag's ``/tf`` and the logical
cameras carry the poses).
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.ros.bag.definitions import TF_MESSAGE, concatenated, installed_text
from omtp_drake.ros.bag.ros1 import ros2_text, ros2_type, ros2_value, stamp_of
from omtp_drake.ros.bag.writer import Ros2Bag
from omtp_drake.ros.comm._core import JOINT_STATE_RATE_HZ, TfBroadcast, TfEdge
from omtp_drake.ros.gazebo.ros_api import LINK_STATES, MODEL_STATES

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session

_log = logging.getLogger(__name__)

#: ``/clock`` in the bag: 100 Hz, the ROS 2 node's step.
CLOCK_RATE_HZ = 100.0
#: Topics a bag leaves out (see the module doc).
EXCLUDED = frozenset({MODEL_STATES, LINK_STATES})
CLOCK = "rosgraph_msgs/msg/Clock"


def _text(type_name: str) -> Optional[str]:
    """A type's ROS 2 text: the shim's ROS 1 definition converted, else the installed one."""
    return ros2_text(type_name) or installed_text(type_name)


def _time(t: float) -> dict[str, int]:
    ns = int(round(t * 1e9))
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def tf_value(edges: list[TfEdge]) -> dict[str, Any]:
    """The edges as a ``tf2_msgs/TFMessage`` value."""
    transforms = []
    for e in edges:
        p, q = e.X_PC.translation(), e.X_PC.rotation().ToQuaternion()
        transforms.append(
            {
                "header": {"stamp": _time(e.time), "frame_id": e.parent},
                "child_frame_id": e.child,
                "transform": {
                    "translation": {"x": float(p[0]), "y": float(p[1]), "z": float(p[2])},
                    "rotation": {"x": q.x(), "y": q.y(), "z": q.z(), "w": q.w()},
                },
            }
        )
    return {"transforms": transforms}


def _drop(message: Any) -> None:
    """The recorder's subscriber callback: the tap has the message already."""


class SessionBag:
    """``session``'s topics into the bag at ``path`` (see the module doc); :meth:`close` finishes it."""

    def __init__(self, session: Session, path: str | Path):
        self.bag = Ros2Bag(path)
        self._session = session
        cell = session.cell
        self._broadcast = TfBroadcast(cell.station.plant, cell.tf)
        self._skipped: set[str] = set()
        for name in (TF_MESSAGE, CLOCK):
            self.bag.add_type(name, concatenated(name, _text))
        for topic in sorted(set(session.sources) - EXCLUDED):
            session.subscribe(topic, _drop, (), 1)
        for topic, (stamp, _, message) in sorted(session.latched.items()):
            self.on_message(topic, stamp, message)
        t = cell.time
        self.bag.write("/tf_static", TF_MESSAGE, tf_value(self._broadcast.static(cell.runtime.context)), t)
        cell.runtime.driver.every(1.0 / CLOCK_RATE_HZ, self._clock)
        cell.runtime.driver.every(1.0 / JOINT_STATE_RATE_HZ, self._tf)
        self._clock()
        self._tf()

    def on_message(self, topic: str, stamp: float, message: Any) -> None:
        """Called by the session for each message published on ``topic``."""
        if topic in EXCLUDED or topic in self._skipped:
            return
        try:
            name, definition = ros2_type(message)
        except (AttributeError, TypeError, ValueError, LookupError) as e:
            self._skipped.add(topic)
            _log.warning(
                "--bag: %s is left out of the bag: %s has no ROS 2 form (%s)", topic, type(message), e
            )
            return
        self.bag.add_type(name, definition)
        header_stamp = stamp_of(message)
        t = self._session.time
        self.bag.write(topic, name, ros2_value(message), t, stamp if header_stamp is None else header_stamp)

    def _clock(self) -> None:
        t = self._session.time
        self.bag.write("/clock", CLOCK, {"clock": _time(t)}, t)

    def _tf(self) -> None:
        cell = self._session.cell
        edges = self._broadcast.moving(cell.runtime.context) + self._broadcast.detected()
        self.bag.write("/tf", TF_MESSAGE, tf_value(edges), cell.time)

    def close(self) -> None:
        """Finishes the bag (called when the run ends)."""
        self.bag.close()
