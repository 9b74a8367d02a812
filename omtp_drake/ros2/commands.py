"""What a ROS 2 peer can tell the cell: the plugins' subscriptions and services
(:func:`omtp_drake.gazebo.plugins.gazebo_plugins`), by ROS 2 types.

==============================  ==================================  =======================================
name                            type                                does
==============================  ==================================  =======================================
``<ns>/set_joint_trajectory``   ``trajectory_msgs/JointTrajectory``  a model's joint pose trajectory plugin
                                                                    (topic; see ``omtp_drake.gazebo``)
``/gripperN/control``           ``std_srvs/SetBool``                vacuum on (``data: true``) / off
``/omtp/conveyor/control``      ``std_srvs/SetBool``                belt on at parameter ``conveyor_power``
                                                                    (0-100, default full power) / off
==============================  ==================================  =======================================

The course's own service types (``omtp_gazebo/VacuumGripperControl``,
``omtp_gazebo/ConveyorBeltControl``) are no PyPI packages, and a peer needs the
type's package to call a service; ``std_srvs/SetBool`` has the same request (one
flag; the belt's power is the node's parameter ``conveyor_power``, ``ros2 param
set /omtp_cell conveyor_power 50``) and answers ``success`` as the course's do,
with the plugin's ``message`` saying what happened (a gripper's held part). What a
request gets is the plugin's (:mod:`omtp_drake.gazebo.vacuum_gripper`,
:mod:`omtp_drake.gazebo.conveyor`).

rclpy runs the callbacks on its executor thread; the cell runs on the caller's. A
callback hands its work to the cell's thread (:meth:`CellCommands.run_pending`,
called between steps) and a service waits for the result, so every change to the
cell happens between two steps of the simulation, at a simulated time.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable
from concurrent.futures import Future
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import OmtpError
from omtp_drake.gazebo import conveyor, vacuum_gripper
from omtp_drake.gazebo.schedule import Subscription
from omtp_drake.gazebo.services import PluginService, ServiceReply
from omtp_drake.ros2 import messages

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The node's parameter of the belt's power when ``/omtp/conveyor/control`` switches it on.
CONVEYOR_POWER = "conveyor_power"
#: The plugins' requests served as ``std_srvs/SetBool`` (the course's types have no ROS 2 package).
SET_BOOL_REQUESTS = (vacuum_gripper.VacuumGripperControl, conveyor.ConveyorBeltControl)


class CellCommands:
    """The subscriptions and services above on ``node`` for ``cell``; ``subscriptions``
    and ``services`` are its Gazebo plugins' (:func:`omtp_drake.gazebo.plugins.gazebo_plugins`)."""

    def __init__(
        self, node: Any, cell: Cell, subscriptions: list[Subscription], services: list[PluginService]
    ):
        from rcl_interfaces.msg import ParameterDescriptor
        from std_srvs.srv import SetBool
        from trajectory_msgs.msg import JointTrajectory

        self._node = node
        self._cell = cell
        self._work: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._stopped = threading.Event()
        for subscription in subscriptions:
            # The plugin's queue: 1 (gazebo_ros's QoS for set_joint_trajectory).
            node.create_subscription(
                JointTrajectory, subscription.topic, self._on_trajectory(subscription), 1
            )
        for service in services:
            if service.request not in SET_BOOL_REQUESTS:
                continue  # served with a type of its own elsewhere in this package
            if service.request is conveyor.ConveyorBeltControl:
                # Dynamic typing: `ros2 param set /omtp_cell conveyor_power 50` sends an integer.
                node.declare_parameter(
                    CONVEYOR_POWER, conveyor.MAX_POWER, ParameterDescriptor(dynamic_typing=True)
                )
            node.create_service(SetBool, service.name, self._set_bool_service(service))

    # ------------------------------------------------------------ the cell's thread

    def run_pending(self) -> None:
        """Runs the work the callbacks handed over (called between steps, on the cell's thread)."""
        while True:
            try:
                work = self._work.get_nowait()
            except queue.Empty:
                break
            work()

    def stop(self) -> None:
        """Services still waiting are answered with a failure (the cell stopped)."""
        self._stopped.set()

    # ------------------------------------------------------------ rclpy's thread

    def _on_trajectory(self, subscription: Subscription) -> Callable[[Any], None]:
        def receive(msg: Any) -> None:
            request = messages.trajectory_request(msg)
            self._work.put(lambda: None if subscription.callback(request) else None)

        return receive

    def run_on_cell(self, work: Callable[[], str]) -> tuple[bool, str]:
        """Runs ``work`` on the cell's thread (for a service of another module); (success, its
        message) when it is done."""
        return self._call(lambda: ServiceReply(True, work()))

    def _call(self, work: Callable[[], ServiceReply]) -> tuple[bool, str]:
        """Runs ``work`` on the cell's thread; (success, its message) when it is done."""
        done: Future[ServiceReply] = Future()

        def run() -> None:
            try:
                done.set_result(work())
            except OmtpError as e:
                done.set_exception(e)

        self._work.put(run)
        while not self._stopped.is_set():
            try:
                reply = done.result(timeout=0.1)
                return reply.success, reply.message
            except TimeoutError:
                continue
            except OmtpError as e:
                return False, str(e)
        return False, "the cell stopped"

    def _set_bool_service(self, service: PluginService) -> Callable[[Any, Any], Any]:
        """``std_srvs/SetBool`` for ``service``: its request read as the plugin's, the plugin's
        reply answered."""

        def serve(request: Any, response: Any) -> Any:
            neutral = self._neutral_request(service.request, bool(request.data))
            if isinstance(neutral, str):
                response.success, response.message = False, neutral
                return response

            def run() -> ServiceReply:
                return service.handler(neutral)

            response.success, response.message = self._call(run)
            return response

        return serve

    def _neutral_request(self, request_type: type, data: bool) -> Any:
        """SetBool's ``data`` as the plugin's request (a str: why it cannot be)."""
        if request_type is conveyor.ConveyorBeltControl:
            value = self._node.get_parameter(CONVEYOR_POWER).value
            if data and (isinstance(value, bool) or not isinstance(value, (int, float))):
                return f"parameter {CONVEYOR_POWER} must be a number, got {value!r}"
            return conveyor.ConveyorBeltControl(float(value) if data else 0.0)
        return vacuum_gripper.VacuumGripperControl(data)
