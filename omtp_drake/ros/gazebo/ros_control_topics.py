"""``gazebo_ros_control`` on a run's ROS 1 graph: the controllers' topics, by ros_controllers' names.

Names only: what each controller does is :mod:`omtp_drake.sim.ros_control`'s.
``<ns>`` is the plugin's ``robotNamespace`` (``/`` by default):

====================================  =====================================  ======================
topic                                 type                                   controller
====================================  =====================================  ======================
``/<ns>/joint_states``                ``sensor_msgs/JointState``             JointStateController,
                                                                             at its ``publish_rate``
``/<ns>/<controller>/command``        ``trajectory_msgs/JointTrajectory``    JointTrajectoryController
``/<ns>/<controller>/command``        ``std_msgs/Float64MultiArray``         JointGroup*Controller
``/<ns>/<controller>/command``        ``std_msgs/Float64``                   Joint{Position,Velocity,
                                                                             Effort}Controller
``/<ns>/<controller>/state``          ``control_msgs/                        JointTrajectoryController,
                                      JointTrajectoryControllerState``       at ``state_publish_rate``
====================================  =====================================  ======================

The trajectory controllers' ``follow_joint_trajectory`` action:
:mod:`omtp_drake.ros.gazebo.ros_control_action`. A refused command is one error line on
the ``rospy`` log, as the controllers log it.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import Controller, RosControl
from omtp_drake.ros.comm._core import gazebo_topic as topic
from omtp_drake.ros.comm.control_interfaces import JointTrajectoryControllerState
from omtp_drake.ros.comm.messages import Header, JointState, JointTrajectoryPoint, Time
from omtp_drake.ros.gazebo.plugin_topics import trajectory_request
from omtp_drake.ros.gazebo.ros_api import PushedSource

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("rospy")

#: Controller types whose ``command`` is one ``std_msgs/Float64`` (one joint).
SINGLE_JOINT_TYPES = (
    "position_controllers/JointPositionController",
    "velocity_controllers/JointVelocityController",
    "effort_controllers/JointEffortController",
    "effort_controllers/JointPositionController",
)


def attach_ros_control(session: Graph) -> None:
    """The ros_control topics of the cell's models on ``session`` (nothing without any)."""
    control = RosControl(session.cell.station)
    for controller in control.of_kind("joint_states"):
        name = topic(controller.namespace, "joint_states")
        session.sources.setdefault(name, PushedSource(JointState))
        session.cell.runtime.driver.every(
            control.period(controller), _publisher(session, control, controller, name)
        )
    for controller in control.controllers:
        if controller.config.kind == "joint_states":
            continue
        name = topic(controller.namespace, f"{controller.name}/command")
        session.subscribe(name, _command(session, control, controller), (), 1)
    for controller in control.of_kind("trajectory"):
        name = topic(controller.namespace, f"{controller.name}/state")
        session.sources.setdefault(name, PushedSource(JointTrajectoryControllerState))
        period = control.state_period(controller)
        if period is not None:
            session.cell.runtime.driver.every(period, _state_publisher(session, control, controller, name))


def _publisher(session: Graph, control: RosControl, controller: Controller, name: str):
    def publish() -> None:
        sample = control.joint_state(session.cell.runtime.context, controller)
        message = JointState(
            header=Header(stamp=Time(sample.stamp)),
            name=list(sample.names),
            position=list(sample.position),
            velocity=list(sample.velocity),
            effort=list(sample.effort),
        )
        session.publish(name, message, sample.stamp)

    return publish


def _state_publisher(session: Graph, control: RosControl, controller: Controller, name: str):
    def publish() -> None:
        if not session.num_subscribers(name):
            return
        state = control.controller_state(session.cell.runtime.context, controller)
        message = JointTrajectoryControllerState(
            header=Header(stamp=Time(state.stamp)),
            joint_names=list(state.joints),
            desired=JointTrajectoryPoint(
                positions=list(state.reference_position), velocities=list(state.reference_velocity)
            ),
            actual=JointTrajectoryPoint(
                positions=list(state.feedback_position), velocities=list(state.feedback_velocity)
            ),
            error=JointTrajectoryPoint(
                positions=list(state.error_position), velocities=list(state.error_velocity)
            ),
        )
        session.publish(name, message, state.stamp)

    return publish


def _command(session: Graph, control: RosControl, controller: Controller):
    def callback(message: Any) -> None:
        context = session.cell.runtime.context
        try:
            if controller.config.kind == "trajectory":
                control.follow(context, controller, trajectory_request(message))
            elif controller.config.type in SINGLE_JOINT_TYPES:
                control.forward(context, controller, [float(message.data)])
            else:
                control.forward(context, controller, [float(x) for x in message.data])
        except (ConfigError, TypeError, AttributeError) as e:
            _log.error("%s: %s", controller.name, e)

    return callback
