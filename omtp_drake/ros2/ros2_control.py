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
``/<ns>/<ctrl>/controller_state``   ``control_msgs/JointTrajectory         JointTrajectoryController, at
                                    ControllerState`` (built here)         each of its updates
``/<ns>/<ctrl>/commands``           ``std_msgs/Float64MultiArray``         ForwardCommandController,
                                                                           JointGroup*Controller
==================================  =====================================  =============================

Each trajectory controller's ``~/follow_joint_trajectory`` action
(``control_msgs/action/FollowJointTrajectory``, built here: :mod:`omtp_drake.ros2.trajectory_action`).
``control_msgs`` is built by :mod:`omtp_drake.ros2.interface_build`; without a compiler the
action and ``~/controller_state`` are off, with one warning. The state's ``reference`` is the
command now, ``feedback`` the joints measured, ``error`` their difference (positions and
velocities), ``output`` the position command (a position controller's); accelerations and
``time_from_start`` are not filled. A refused command is one error line on the node's log.
A message is built on its schedule only while someone would get it
(:func:`~omtp_drake.ros2.audience.heard`).
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
from omtp_drake.ros2 import interface_build, messages
from omtp_drake.ros2.audience import heard
from omtp_drake.ros2.trajectory_action import FollowJointTrajectoryServers
from omtp_drake.sim.ros_control import Controller, ControllerStateSample, Periodic, RosControl
from omtp_drake.sim.trajectory_request import TrajectoryRequest

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: Simulated seconds of joint states a broadcaster keeps for a subscriber that lags (the
#: cell runs faster than real time; a reliable KEEP_LAST writer drops what overflows).
QUEUE_S = 60.0

#: Why the action and the state topic are missing where control_msgs cannot be built, said once.
NO_CONTROL_MSGS = (
    "follow_joint_trajectory and controller_state are not served (send trajectories on "
    "~/joint_trajectory): control_msgs has no PyPI package and its type support could not be built here"
)


def _control_msgs(node: Any) -> bool:
    """Whether ``control_msgs`` can be imported (built here once), else one warning saying why not."""
    return interface_build.activated(NO_CONTROL_MSGS, node.get_logger().warning)


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
            publisher = node.create_publisher(
                JointState, topic(controller.namespace, "joint_states"), _depth(period)
            )
            self._broadcasters.append((controller, Periodic(period), publisher))
        for controller in self._control.of_kind("trajectory"):
            name = topic(controller.namespace, f"{controller.name}/joint_trajectory")
            node.create_subscription(
                JointTrajectory, name, self._handler(controller, messages.trajectory_request), 10
            )
        for controller in self._control.of_kind("forward"):
            name = topic(controller.namespace, f"{controller.name}/commands")
            node.create_subscription(Float64MultiArray, name, self._handler(controller, _values), 10)
        self.actions: FollowJointTrajectoryServers | None = None
        self._states: list[tuple[Controller, Periodic, Any]] = []
        if self._control.of_kind("trajectory") and _control_msgs(node):
            self.actions = FollowJointTrajectoryServers(node, cell, self._control, self._work.put)
            self._states = self._state_publishers()

    def _state_publishers(self) -> list[tuple[Controller, Periodic, Any]]:
        """Each trajectory controller's ``~/controller_state`` publisher and its schedule."""
        from control_msgs.msg import JointTrajectoryControllerState

        out = []
        for controller in self._control.of_kind("trajectory"):
            period = self._control.state_period(controller)
            if period is None:
                continue
            name = topic(controller.namespace, f"{controller.name}/controller_state")
            publisher = self._node.create_publisher(JointTrajectoryControllerState, name, _depth(period))
            out.append((controller, Periodic(period), publisher))
        return out

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
        """The broadcasters' joint states due at ``t``, and the action goals' feedback and outcomes."""
        if self.actions is not None:
            self.actions.check(t)
        for controller, periodic, publisher in self._broadcasters:
            if periodic.due(t) and heard(publisher):
                sample = self._control.joint_state(self._cell.runtime.context, controller)
                msg = messages.to_ros(
                    JointStates(
                        sample.stamp, tuple(sample.names), tuple(sample.position), tuple(sample.velocity)
                    )
                )
                msg.effort = list(sample.effort)
                publisher.publish(msg)
        for controller, periodic, publisher in self._states:
            if periodic.due(t) and heard(publisher):
                state = self._control.controller_state(self._cell.runtime.context, controller)
                publisher.publish(_state_message(publisher.msg_type, state, controller.config.interface))


def _depth(period: float) -> int:
    """A publisher's KEEP_LAST depth: :data:`QUEUE_S` of messages every ``period`` s."""
    return max(100, int(QUEUE_S / period))


def _state_message(msg_type: Any, state: ControllerStateSample, interface: str) -> Any:
    """The ``control_msgs/JointTrajectoryControllerState`` of ``state``, whose controller commands
    ``interface``."""
    from trajectory_msgs.msg import JointTrajectoryPoint

    msg = msg_type(header=messages.header(state.stamp), joint_names=list(state.joints))
    msg.reference = JointTrajectoryPoint(
        positions=list(state.reference_position), velocities=list(state.reference_velocity)
    )
    msg.feedback = JointTrajectoryPoint(
        positions=list(state.feedback_position), velocities=list(state.feedback_velocity)
    )
    msg.error = JointTrajectoryPoint(
        positions=list(state.error_position), velocities=list(state.error_velocity)
    )
    if interface == "position":
        msg.output = JointTrajectoryPoint(positions=list(state.reference_position))
    msg.speed_scaling_factor = 1.0
    return msg


def _values(msg: Any) -> list[float]:
    return [float(x) for x in msg.data]
