"""What a ROS 2 peer can tell the cell: the models' trajectory plugins, the grippers and the belt.

==============================  ==================================  =======================================
name                            type                                does
==============================  ==================================  =======================================
``<ns>/set_joint_trajectory``   ``trajectory_msgs/JointTrajectory``  a model's joint pose trajectory plugin
                                                                    (topic; see ``omtp_drake.gazebo``)
``/gripperN/control``           ``std_srvs/SetBool``                vacuum on (``data: true``) / off
``/omtp/conveyor/control``      ``std_srvs/SetBool``                belt on at parameter ``conveyor_power``
                                                                    (0-100, default 100) / off
==============================  ==================================  =======================================

The course's own service types (``omtp_gazebo/VacuumGripperControl``,
``omtp_gazebo/ConveyorBeltControl``) are no PyPI packages, and a peer needs the
type's package to call a service; ``std_srvs/SetBool`` has the same request (one
flag; the belt's power is the node's parameter ``conveyor_power``, ``ros2 param
set /omtp_cell conveyor_power 50``) and answers ``success`` as the course's do,
with a ``message`` saying what happened (a gripper's held part).

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
from omtp_drake.gazebo.schedule import Subscription
from omtp_drake.ros2 import messages

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: The belt's power when ``/omtp/conveyor/control`` switches it on and the parameter is unset.
DEFAULT_CONVEYOR_POWER = 100.0


class CellCommands:
    """The subscriptions and services above on ``node`` for ``cell``; ``subscriptions``
    are its Gazebo plugins' (:func:`omtp_drake.gazebo.plugins.gazebo_plugins`)."""

    def __init__(self, node: Any, cell: Cell, subscriptions: list[Subscription]):
        from rcl_interfaces.msg import ParameterDescriptor
        from std_srvs.srv import SetBool
        from trajectory_msgs.msg import JointTrajectory

        from omtp_drake.ros.gazebo.cell_services import gripper_plugins

        self._node = node
        self._cell = cell
        self._work: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._stopped = threading.Event()
        for subscription in subscriptions:
            # The plugin's queue: 1 (gazebo_ros's QoS for set_joint_trajectory).
            node.create_subscription(
                JointTrajectory, subscription.topic, self._on_trajectory(subscription), 1
            )
        for robot, plugin in gripper_plugins(cell).items():
            node.create_service(SetBool, f"/{plugin}/control", self._gripper_service(robot))
        if cell.station.conveyor is not None:
            # Dynamic typing: `ros2 param set /omtp_cell conveyor_power 50` sends an integer.
            node.declare_parameter(
                "conveyor_power", DEFAULT_CONVEYOR_POWER, ParameterDescriptor(dynamic_typing=True)
            )
            node.create_service(SetBool, "/omtp/conveyor/control", self._conveyor_service)

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
        return self._call(work)

    def _call(self, work: Callable[[], str]) -> tuple[bool, str]:
        """Runs ``work`` on the cell's thread; (success, its message) when it is done."""
        done: Future[str] = Future()

        def run() -> None:
            try:
                done.set_result(work())
            except OmtpError as e:
                done.set_exception(e)

        self._work.put(run)
        while not self._stopped.is_set():
            try:
                return True, done.result(timeout=0.1)
            except TimeoutError:
                continue
            except OmtpError as e:
                return False, str(e)
        return False, "the cell stopped"

    def _gripper_service(self, robot: str) -> Callable[[Any, Any], Any]:
        gripper = self._cell.gripper(robot)

        def control(request: Any, response: Any) -> Any:
            def switch() -> str:
                gripper.on() if request.data else gripper.off()
                held = f"; holding {gripper.part}" if gripper.attached else ""
                return f"vacuum {'on' if request.data else 'off'}{held}"

            response.success, response.message = self._call(switch)
            return response

        return control

    def _conveyor_service(self, request: Any, response: Any) -> Any:
        value = self._node.get_parameter("conveyor_power").value
        if request.data and not isinstance(value, (int, float)):
            response.success, response.message = (
                False,
                f"parameter conveyor_power must be a number, got {value!r}",
            )
            return response
        power = float(value) if request.data else 0.0

        def switch() -> str:
            self._cell.set_conveyor_power(power)
            return f"conveyor power {power:g}"

        response.success, response.message = self._call(switch)
        return response
