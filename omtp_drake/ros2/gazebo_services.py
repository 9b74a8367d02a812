"""Gazebo's model services on ROS 2, as gazebo_ros's ``gazebo_ros_factory`` and
``gazebo_ros_state`` plugins serve them, over :mod:`omtp_drake.gazebo.world_services`'s rules:

=======================  ===============================  ==========================================
service                  type                             what (the layer's rules)
=======================  ===============================  ==========================================
``/spawn_entity``        ``gazebo_msgs/srv/SpawnEntity``  a course part (URDF or SDF) at a pose
``/delete_entity``       ``gazebo_msgs/srv/DeleteEntity`` removes a part
``/get_entity_state``    ``gazebo_msgs/srv/GetEntityState`` a model's or ``model::link``'s state
``/set_entity_state``    ``gazebo_msgs/srv/SetEntityState`` moves a part (pose and twist)
``/reset_world``         ``std_srvs/srv/Empty``           the parts back where they entered
``/reset_simulation``    ``std_srvs/srv/Empty``           refused: one error line (the layer's)
``/pause_physics``       ``std_srvs/srv/Empty``           simulated time stops (:class:`PhysicsServices`)
``/unpause_physics``     ``std_srvs/srv/Empty``           it runs again
=======================  ===============================  ==========================================

``gazebo_msgs`` is built here from its definitions (:mod:`omtp_drake.ros2.interface_build`):
real rclpy type support, so a peer's ``from gazebo_msgs.srv import SpawnEntity`` client talks
to these. Where it cannot be built (no compiler), :func:`serve_gazebo_services` says why once
and serves none of them (the ``std_srvs`` ones are served regardless). A request the layer
refuses (a model that is no part) answers ``success: False`` with the layer's message, as
gazebo_ros's plugins answer a bad request.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.errors import ConfigError
from omtp_drake.gazebo.spawn import Reply
from omtp_drake.gazebo.world_services import WorldServices
from omtp_drake.ros.tf.convert import unit_quaternion
from omtp_drake.ros2 import interface_build, messages

_log = logging.getLogger("gazebo")

#: Said once when the services cannot be served (followed by why).
NOT_SERVED = (
    "Gazebo's model services (spawn_entity, delete_entity, get_entity_state, set_entity_state) are not "
    "served on ROS 2: gazebo_msgs has no PyPI package and its type support could not be built here"
)

RunOnCell = Callable[[Callable[[], str]], tuple[bool, str]]


def serve_gazebo_services(node: Any, api: WorldServices, run_on_cell: RunOnCell) -> bool:
    """Serves the ``gazebo_msgs`` services above on ``node`` (rclpy) over ``api``; False (and one
    warning saying why) when ``gazebo_msgs`` cannot be built here."""
    if not interface_build.activated(NOT_SERVED, _log.warning):
        return False
    _GazeboServices(node, api, run_on_cell)
    return True


class PhysicsServices:
    """gazebo_ros_init's ``/pause_physics``, ``/unpause_physics``, ``/reset_world`` and
    ``/reset_simulation`` (``std_srvs/srv/Empty``, served in every world, as gazebo_ros loads that
    plugin with every world): while paused the node does not advance the cell (nor ``/clock``), as
    Gazebo's paused physics; unpaused, realtime pacing counts from then (Gazebo does not catch up).
    ``/reset_simulation`` is the layer's refusal (``std_srvs/Empty`` carries no failure: the
    caller gets its empty reply, the node one error line), as ROS 1's is one NotSupportedError."""

    def __init__(self, node: Any, api: WorldServices, run_on_cell: RunOnCell):
        from std_srvs.srv import Empty

        self.api = api
        #: Whether a peer paused the physics (read by the node between steps).
        self.paused = False
        self._run_on_cell = run_on_cell
        node.create_service(Empty, "/pause_physics", lambda q, r: self._call(r, lambda: self._pause(True)))
        node.create_service(Empty, "/unpause_physics", lambda q, r: self._call(r, lambda: self._pause(False)))
        node.create_service(Empty, "/reset_world", lambda q, r: self._call(r, self._reset_world))
        node.create_service(Empty, "/reset_simulation", lambda q, r: self._call(r, self._reset_simulation))

    def _call(self, response: Any, work: Callable[[], str]) -> Any:
        # std_srvs/Empty has no success field: a failed call is logged, as rclcpp's would be.
        ok, message = self._run_on_cell(work)
        if not ok:
            _log.error("%s", message)
        return response

    def _pause(self, on: bool) -> str:
        cell = self.api.world.cell
        if self.paused and not on:
            cell.runtime.simulator.ResetStatistics()
        self.paused = on
        _log.info("gazebo: physics %s at t = %.3f s", "paused" if on else "running", cell.time)
        return "paused" if on else "running"

    def _reset_world(self) -> str:
        self.api.spawner.reset_world()
        return "reset_world"

    def _reset_simulation(self) -> str:
        return self.api.reset_simulation("/reset_simulation", "/reset_world")


def _rigid(msg: Any, what: str) -> RigidTransform:
    """A ``geometry_msgs/msg/Pose`` as a RigidTransform (ConfigError naming ``what`` if not finite)."""
    p = np.array([msg.position.x, msg.position.y, msg.position.z], dtype=float)
    if not np.all(np.isfinite(p)):
        raise ConfigError(f"{what}: the position {p.tolist()} is not finite")
    return RigidTransform(unit_quaternion(msg.orientation, what), p)


class _GazeboServices:
    """The services on ``node``; each request's work runs on the cell's thread (``run_on_cell``)."""

    def __init__(self, node: Any, api: WorldServices, run_on_cell: RunOnCell):
        from gazebo_msgs.srv import DeleteEntity, GetEntityState, SetEntityState, SpawnEntity

        self.api = api
        self._run_on_cell = run_on_cell
        node.create_service(SpawnEntity, "/spawn_entity", self.spawn)
        node.create_service(DeleteEntity, "/delete_entity", self.delete)
        node.create_service(GetEntityState, "/get_entity_state", self.get_state)
        node.create_service(SetEntityState, "/set_entity_state", self.set_state)

    def _on_cell(self, work: Callable[[], Any]) -> Any:
        """``work()``'s reply, or a failed one with the error's message (logged)."""
        replies: list[Any] = []

        def run() -> str:
            replies.append(work())
            return replies[-1].status_message

        ok, message = self._run_on_cell(run)
        if ok and replies:
            return replies[0]
        _log.error("%s", message)
        return Reply(False, message)

    def spawn(self, request: Any, response: Any) -> Any:
        reply = self._on_cell(
            lambda: self.api.spawner.spawn(
                "/spawn_entity",
                request.name,
                request.xml,
                _rigid(request.initial_pose, "initial_pose"),
                request.reference_frame,
            )
        )
        response.success, response.status_message = reply.success, reply.status_message
        return response

    def delete(self, request: Any, response: Any) -> Any:
        reply = self._on_cell(lambda: self.api.delete_model(request.name))
        response.success, response.status_message = reply.success, reply.status_message
        return response

    def get_state(self, request: Any, response: Any) -> Any:
        """A ``model`` or a ``model::link`` (gazebo_ros_state reads either) in ``reference_frame``."""
        name, frame = request.name, request.reference_frame
        read = self.api.get_link_state if "::" in name else self.api.get_model_state
        reply = self._on_cell(lambda: read(name, frame))
        response.success = reply.success
        if reply.success:
            response.header = messages.header(self.api.world.cell.time, frame)
            state = response.state
            state.name, state.reference_frame, state.pose = name, frame, messages.pose(reply.X)
            v, w = state.twist.linear, state.twist.angular
            v.x, v.y, v.z, w.x, w.y, w.z = (float(x) for x in reply.twist)
        return response

    def set_state(self, request: Any, response: Any) -> Any:
        state = request.state
        v, w = state.twist.linear, state.twist.angular
        reply = self._on_cell(
            lambda: self.api.set_model_state(
                state.name,
                lambda: _rigid(state.pose, "state.pose"),
                np.array([v.x, v.y, v.z], dtype=float),
                np.array([w.x, w.y, w.z], dtype=float),
                state.reference_frame,
            )
        )
        response.success = reply.success
        return response
