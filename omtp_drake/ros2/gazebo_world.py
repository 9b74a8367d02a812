"""Gazebo's world plugins on ROS 2: the model and link states (:mod:`omtp_drake.gazebo.model_states`,
gazebo_ros_state's rules) and the course's spawner (:mod:`omtp_drake.gazebo.spawner`).

=========================  =====================================  ======================================
name                       type                                   what
=========================  =====================================  ======================================
``/gazebo/model_states``   ``gazebo_msgs/ModelStates``            every model in the world, plugin's rate
``/gazebo/link_states``    ``gazebo_msgs/LinkStates``             every link of them, the plugin's rate
the spawner's services     ``std_srvs/srv/Empty``                 start / stop (the course's names, type)
``/spawned_part``          ``std_msgs/Header`` (transient local)  each spawn (``frame_id``: the object)
``/pause_physics`` ...     ``std_srvs/srv/Empty``                 gazebo_ros_init's (``gazebo_services``)
=========================  =====================================  ======================================

No ``gazebo_msgs`` wheel is on PyPI: the states go out with its type support built here, else
through Cyclone DDS (:mod:`omtp_drake.ros2.packed_topics`), only while someone would get them;
Gazebo's model services (``spawn_entity``,
``delete_entity``, ``get_entity_state``, ``set_entity_state``) are served with real type support
built here (:mod:`omtp_drake.ros2.gazebo_services`), if the cell has what they act on in the
course (parts, or its spawner). ROS 2's std_srvs has the spawner's own type, so its services are
served as under ros-run.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.gazebo.model_states import state_publications
from omtp_drake.gazebo.spawner import spawner
from omtp_drake.gazebo.world import GazeboWorld
from omtp_drake.gazebo.world_services import WorldServices
from omtp_drake.ros.bag.definitions import LINK_STATES_TYPE, MODEL_STATES_TYPE
from omtp_drake.ros2 import cdr, messages
from omtp_drake.ros2.gazebo_services import PhysicsServices, serve_gazebo_services
from omtp_drake.ros2.packed_topics import PackedTopics

if TYPE_CHECKING:
    from omtp_drake.script import Cell

_log = logging.getLogger("gazebo")


def _numbers(states: Any) -> tuple[list[tuple[float, ...]], list[tuple[float, ...]]]:
    """(poses as (x, y, z, qx, qy, qz, qw), twists) of the layer's entity states."""
    poses: list[tuple[float, ...]] = []
    for X in states.pose:
        p, q = X.translation(), X.rotation().ToQuaternion()
        poses.append((p[0], p[1], p[2], q.x(), q.y(), q.z(), q.w()))
    return poses, list(states.twist)


class GazeboWorldTopics:
    """The topics and services above for ``cell`` on ``node`` (rclpy), the states by ``topics``'
    route; ``run_on_cell(work)`` runs a service's ``work`` on the cell's thread and returns
    (success, message) (:meth:`omtp_drake.ros2.commands.CellCommands.run_on_cell`)."""

    def __init__(
        self,
        node: Any,
        cell: Cell,
        topics: PackedTopics,
        run_on_cell: Callable[[Callable[[], str]], tuple[bool, str]],
    ):
        self.world = GazeboWorld(cell)
        self._cell = cell
        self._states = [
            (p.poll, topics.topic(p.topic, type_name, depth=1))
            for p, type_name in zip(
                state_publications(self.world, "ros2"), (MODEL_STATES_TYPE, LINK_STATES_TYPE)
            )
        ]
        #: Spawner calls that spawned nothing (each logged once).
        self.empty_calls: list[str] = []
        self._spawned: Optional[tuple[Callable[[float], list[Any]], Any]] = None
        found = spawner(self.world, self.empty_calls)
        if found is not None:
            self._serve(node, found, run_on_cell)
        # Gazebo's model services act on the course's parts (spawned, deleted, their states read and
        # set): served where the cell has parts or its spawner, as gazebo_msgs can be built here
        # (omtp_drake.ros2.gazebo_services). A world of fixed models and robots (the tutorial robot's)
        # has neither, and builds nothing.
        api = WorldServices(self.world)
        self.physics = PhysicsServices(node, api, run_on_cell)
        if found is not None or self.world.models.parts:
            serve_gazebo_services(node, api, run_on_cell)

    def _serve(
        self, node: Any, found: Any, run_on_cell: Callable[[Callable[[], str]], tuple[bool, str]]
    ) -> None:
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from std_msgs.msg import Header
        from std_srvs.srv import Empty

        for service in found.services:

            def call(request: Any, response: Any, service: Any = service) -> Any:
                def work() -> str:
                    service.call()
                    return service.name

                # std_srvs/Empty has no success field: a failed call is logged, as rclcpp's would be.
                ok, message = run_on_cell(work)
                if not ok:
                    _log.error("%s: %s", service.name, message)
                return response

            node.create_service(Empty, service.name, call)
        if found.publication is not None:
            latched = QoSProfile(
                depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
            )
            publisher = node.create_publisher(Header, found.publication.topic, latched)
            self._spawned = (found.publication.poll, publisher)
        self._header = Header

    def __call__(self, t: float) -> None:
        """What is due at ``t``: the states, and each spawn's ``/spawned_part``."""
        for poll, topic in self._states:
            if not topic.wanted():  # nothing reads it: not even computed (the layer's messages cost)
                continue
            for states in poll(t):
                poses, twists = _numbers(states)
                topic.write(cdr.model_states(states.name, poses, twists), self._cell.time, states.stamp)
        if self._spawned is not None:
            poll, publisher = self._spawned
            for m in poll(t):
                publisher.publish(self._header(stamp=messages.stamp(m.stamp), frame_id=m.frame_id))

    def close(self) -> None:
        """Leaves the DDS graph (the node's Ros2Cell closes this)."""
        for _, topic in self._states:
            topic.close()
