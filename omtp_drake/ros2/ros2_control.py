"""``gazebo_ros2_control`` on the ROS 2 node: the controllers' topics, by ros2_controllers' names.

Names, types and QoS only: what each controller does is :mod:`omtp_drake.sim.ros_control`'s.
``<ns>`` is the plugin's ``<ros><namespace>`` (``/`` by default):

==================================  =====================================  =============================
topic                               type                                   controller
==================================  =====================================  =============================
``/<ns>/joint_states``              ``sensor_msgs/JointState``             JointStateBroadcaster, at its
                                                                           ``update_rate`` (else the
                                                                           controller manager's)
``/<ns>/<ctrl>/joint_trajectory``   ``trajectory_msgs/JointTrajectory``    JointTrajectoryController
``/<ns>/<ctrl>/commands``           ``std_msgs/Float64MultiArray``         ForwardCommandController,
                                                                           JointGroup*Controller
==================================  =====================================  =============================

Not served: the trajectory controller's ``~/controller_state`` and its
``~/follow_joint_trajectory`` action are ``control_msgs`` types, which no PyPI package
provides (docs/ros_control.md). A refused command is one error line on the node's log.
Without a launch file the YAML's controllers are active, as if each was spawned in order
(:func:`~omtp_drake.scenario.ros_control_parse.spawned_only`).
"""

from __future__ import annotations

import queue
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import ConfigError
from omtp_drake.gazebo.messages import JointStates
from omtp_drake.gazebo.schedule import topic
from omtp_drake.ros2 import messages
from omtp_drake.sim.ros_control import Controller, Periodic, RosControl
from omtp_drake.sim.trajectory_request import TrajectoryRequest

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: Simulated seconds of joint states a broadcaster keeps for a subscriber that lags (the
#: cell runs faster than real time; a reliable KEEP_LAST writer drops what overflows).
QUEUE_S = 60.0

#: Why the action and the state topic are missing, said once where a user meets them.
NO_CONTROL_MSGS = (
    "follow_joint_trajectory and controller_state need control_msgs, which no PyPI package provides: "
    "send trajectories on ~/joint_trajectory"
)


class Ros2Control:
    """The controllers' topics of ``cell`` on ``node`` (an rclpy node). Callbacks hand
    their work to the cell's thread (:meth:`run_pending`, between steps)."""

    def __init__(self, node: Any, cell: Cell):
        from sensor_msgs.msg import JointState
        from std_msgs.msg import Float64MultiArray
        from trajectory_msgs.msg import JointTrajectory

        self._node = node
        self._cell = cell
        self._control = RosControl(cell.station)
        self._work: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._broadcasters: list[tuple[Controller, Periodic, Any]] = []
        for controller in self._control.of_kind("joint_states"):
            period = self._control.period(controller)
            depth = max(100, int(QUEUE_S / period))
            publisher = node.create_publisher(JointState, topic(controller.namespace, "joint_states"), depth)
            self._broadcasters.append((controller, Periodic(period), publisher))
        for controller in self._control.of_kind("trajectory"):
            name = topic(controller.namespace, f"{controller.name}/joint_trajectory")
            node.create_subscription(
                JointTrajectory, name, self._handler(controller, messages.trajectory_request), 10
            )
        for controller in self._control.of_kind("forward"):
            name = topic(controller.namespace, f"{controller.name}/commands")
            node.create_subscription(Float64MultiArray, name, self._handler(controller, _values), 10)
        if self._control.of_kind("trajectory"):
            node.get_logger().info(NO_CONTROL_MSGS)

    def _handler(self, controller: Controller, convert: Callable[[Any], Any]) -> Callable[[Any], None]:
        def on_message(msg: Any) -> None:
            request = convert(msg)
            self._work.put(lambda: self._apply(controller, request))

        return on_message

    def _apply(self, controller: Controller, request: Any) -> None:
        context = self._cell.runtime.context
        try:
            if isinstance(request, TrajectoryRequest):
                self._control.follow(context, controller, request)
            else:
                self._control.forward(context, controller, request)
        except ConfigError as e:
            self._node.get_logger().error(f"{controller.name}: {e}")

    def run_pending(self) -> None:
        """Applies the commands received since the last call (on the cell's thread)."""
        while True:
            try:
                work = self._work.get_nowait()
            except queue.Empty:
                return
            work()

    def publish(self, t: float) -> None:
        """The broadcasters' joint states due at ``t``."""
        for controller, periodic, publisher in self._broadcasters:
            if periodic.due(t):
                sample = self._control.joint_state(self._cell.runtime.context, controller)
                msg = messages.to_ros(
                    JointStates(
                        sample.stamp, tuple(sample.names), tuple(sample.position), tuple(sample.velocity)
                    )
                )
                msg.effort = list(sample.effort)
                publisher.publish(msg)


def _values(msg: Any) -> list[float]:
    return [float(x) for x in msg.data]
