"""The cell as a ROS 2 node: :class:`Ros2Cell` puts a scripted
:class:`~omtp_drake.script.Cell` on a DDS network and steps it in simulated time.

One node, ``/omtp_cell``, in its own rclpy context (the domain and discovery range of
:mod:`omtp_drake.ros2.network`), publishes the topics of
:mod:`omtp_drake.ros2.topics` and serves the commands of
:mod:`omtp_drake.ros2.commands`. rclpy's executor runs on a thread of its own, so
that peers are answered while the cell steps; the cell itself only changes on the
thread that calls :meth:`Ros2Cell.step`. Its parameter ``use_sim_time`` is true, as
gazebo_ros's nodes': its own clock reads the simulated time (:class:`CellClock`).

Typical use (what ``omtp-drake ros2`` does)::

    with Cell("lecture6_assignment1") as cell, Ros2Cell(cell, choose_network()) as node:
        while cell.time < 30.0:
            node.step()
"""

from __future__ import annotations

import logging
import re
import threading
import time
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.gazebo.joint_states import JOINT_STATE_RATE_HZ
from omtp_drake.gazebo.plugins import gazebo_plugins
from omtp_drake.gazebo.schedule import Periodic
from omtp_drake.ros.moveit.description import robot_description
from omtp_drake.ros2.bag import record_publishers
from omtp_drake.ros2.commands import CellCommands
from omtp_drake.ros2.course_topics import CourseTopics
from omtp_drake.ros2.gazebo_world import GazeboWorldTopics
from omtp_drake.ros2.network import Ros2Network, cell_participant_profile, import_rclpy
from omtp_drake.ros2.packed_topics import PackedTopics
from omtp_drake.ros2.ros2_control import Ros2Control
from omtp_drake.ros2.tf_publisher import TfTopics
from omtp_drake.ros2.topics import CellTopics
from omtp_drake.viz.meshcat import free_meshcats_here

if TYPE_CHECKING:
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.dds_types import CycloneParticipant
    from omtp_drake.script import Cell

_log = logging.getLogger("gazebo")

#: The node's name (Gazebo's is ``/gazebo``; one node serves the whole cell here).
NODE_NAME = "omtp_cell"
#: Simulated time between two steps (s): ``/clock``'s period, 100 Hz.
STEP = 0.01


def urdf_for_ros2(cell: Cell) -> str:
    """The cell's URDF (:func:`~omtp_drake.ros.moveit.description.robot_description`) with its
    meshes' absolute paths as ``file://`` URIs, the form rviz2 and robot_state_publisher
    resolve (a bare path is no URI to ROS 2's resource retriever)."""
    return re.sub(r'filename="/', 'filename="file:///', robot_description(cell))


def _cell_node(context: Any, network: Ros2Network) -> Any:
    """The node :data:`NODE_NAME` in ``context`` (initialized here on ``network``'s domain), its
    participant made with the cell's Fast DDS profile
    (:func:`~omtp_drake.ros2.network.cell_participant_profile`)."""
    import rclpy
    from rclpy.parameter import Parameter
    from rclpy.signals import SignalHandlerOptions

    with cell_participant_profile():  # the participant comes with the context's first node
        rclpy.init(
            context=context, domain_id=network.domain_id, signal_handler_options=SignalHandlerOptions.NO
        )
        try:
            return rclpy.create_node(
                NODE_NAME,
                context=context,
                parameter_overrides=[Parameter("use_sim_time", Parameter.Type.BOOL, True)],
            )
        except BaseException:
            context.try_shutdown()
            raise


class CellClock:
    """``node``'s clock (rclpy's ROS clock: what its action servers, logs and parameter events
    stamp) set to the cell's simulated time at each step.

    With ``use_sim_time`` rclpy's time source follows ``/clock`` by subscribing to it, and this
    node publishes ``/clock`` itself at every step: each of its own messages came back through
    Fast DDS into its executor (a delivery on the publishing thread, a take and a callback on the
    executor's), 100 a simulated second, listened to or not. Measured on ``lecture6_assignment1``
    with nobody else listening: the executor thread 98-160 CPU ms per simulated s, and the
    stepping thread 150 more. The cell knows its own time: the clock is set directly, and the time
    source's subscription dropped (the node subscribes to no topic it publishes).
    """

    def __init__(self, node: Any):
        for subscription in [s for s in node.subscriptions if s.topic_name == "/clock"]:
            node.destroy_subscription(subscription)
        self._clock = node.get_clock()

    def __call__(self, t: float) -> None:
        """The clock reads ``t`` (simulated s) from now on."""
        from rclpy.time import Time

        self._clock.set_ros_time_override(
            Time(nanoseconds=int(round(t * 1e9)), clock_type=self._clock.clock_type)
        )


class CellCyclone:
    """The cell's Cyclone DDS participant on ``network`` (:mod:`omtp_drake.ros2.dds_types`), made at
    the first call and the same after: only the course's own types (the grippers, the break beam),
    and /tf and Gazebo's states where their rclpy types cannot be built, need it. A cell without
    them (a robot of the user's own, with the types built) neither imports Cyclone DDS (0.3-0.5 s
    of CPU at every start) nor puts a second participant on the domain for every peer to discover.
    """

    def __init__(self, network: Ros2Network):
        self._network = network
        self._participant: Optional[CycloneParticipant] = None

    def __call__(self) -> CycloneParticipant:
        if self._participant is None:
            from omtp_drake.ros2.dds_types import CycloneParticipant

            self._participant = CycloneParticipant(self._network)
        return self._participant


class Ros2Cell:
    """``cell`` as the ROS 2 node :data:`NODE_NAME` on ``network``.

    Use it as a context manager, or call :meth:`close`: it stops the executor and
    shuts its rclpy context down (nothing of it outlives the call).
    """

    def __init__(self, cell: Cell, network: Ros2Network, bag: Optional[Ros2Bag] = None):
        rclpy = import_rclpy()
        from rclpy.executors import SingleThreadedExecutor

        self.cell = cell
        self.network = network
        #: The URDF ``/robot_description`` carries.
        self.description = urdf_for_ros2(cell)
        network.apply()
        self._context = rclpy.Context()
        self.node = _cell_node(self._context, network)
        try:
            self._clock = CellClock(self.node)
            self._clock(cell.time)
            if bag is not None:  # --bag: what the node publishes goes into the bag too
                record_publishers(self.node, bag, lambda: cell.time)
            plugins = gazebo_plugins(cell)
            for line in plugins.warnings:
                _log.warning(line)
            self.topics = CellTopics(self.node, cell, plugins, self.description)
            self.commands = CellCommands(self.node, cell, plugins.subscriptions, plugins.services)
            self.control = Ros2Control(self.node, cell)
            # The course's own types over a Cyclone DDS participant; /tf, /tf_static
            # (omtp_drake.ros2.tf_publisher) and Gazebo's states by rclpy with the types built
            # here, else by Cyclone too (packed_topics); /tf at the joint states' rate, as
            # robot_state_publisher follows /joint_states
            dds = CellCyclone(network)
            self._course_topics = CourseTopics(self.node, dds, plugins.publications, bag)
            #: Who writes /tf and Gazebo's states (``.route``: "rclpy" or "cyclone").
            self.packed = PackedTopics(self.node, dds, bag)
            self._tf_topics = TfTopics(cell, self.packed)
            self.gazebo = GazeboWorldTopics(self.node, cell, self.packed, self.commands.run_on_cell)
            self.tf = Periodic(1.0 / JOINT_STATE_RATE_HZ, self._tf_topics)
            self._executor = SingleThreadedExecutor(context=self._context)
            self._executor.add_node(self.node)
        except BaseException:
            self._context.try_shutdown()
            raise
        free_meshcats_here()  # before the executor's thread runs Python
        self._thread = threading.Thread(target=self._spin, name="omtp_cell rclpy executor", daemon=True)
        self._thread.start()
        self._closed = False
        self.topics.publish(cell.time)
        self._course_topics(cell.time)
        self.control.publish(cell.time)
        self.tf(cell.time)
        self.gazebo(cell.time)

    def _spin(self) -> None:
        from rclpy.executors import ExternalShutdownException

        try:
            self._executor.spin()
        except ExternalShutdownException:
            pass

    def step(self, dt: float = STEP) -> None:
        """Applies what peers asked for meanwhile, advances the cell by ``dt`` and
        publishes what is due (the plugins' world edits run inside the advance)."""
        self.commands.run_pending()
        self.control.run_pending()
        if self.gazebo.physics.paused:  # /pause_physics: time stands still until /unpause_physics
            time.sleep(dt)
            return
        self.cell.runtime.advance_to(self.cell.time + dt)
        self._clock(self.cell.time)
        self.topics.publish(self.cell.time)
        self._course_topics(self.cell.time)
        self.control.publish(self.cell.time)
        self.tf(self.cell.time)
        self.gazebo(self.cell.time)

    def close(self) -> None:
        """Stops the executor, destroys the node, shuts the context down."""
        if self._closed:
            return
        self._closed = True
        self.commands.stop()
        self._executor.shutdown(timeout_sec=2.0)
        self.node.destroy_node()
        self._tf_topics.close()
        self._course_topics.close()
        self.gazebo.close()
        self._context.try_shutdown()
        self._thread.join(timeout=5.0)

    def __enter__(self) -> Ros2Cell:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
