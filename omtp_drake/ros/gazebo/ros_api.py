"""Gazebo's own ROS API on a ROS 1 run (``gazebo_ros``'s API plugin), under ``/gazebo``: the
plugin layer's model and link states (:mod:`omtp_drake.gazebo.model_states`, the ``noetic``
branch: one message per physics update while subscribed) and its model services
(:mod:`omtp_drake.gazebo.world_services`) as ``gazebo_msgs`` topics and services. The rules
are the layer's; here requests and replies are converted field for field.

A ``gazebo_msgs/ModelState`` published on ``/gazebo/set_model_state`` moves the model as the
service does (Gazebo subscribes to that topic too).

Services: ``get_model_state``, ``set_model_state``, ``get_link_state``,
``spawn_urdf_model`` and ``spawn_sdf_model``, ``delete_model``, ``pause_physics``,
``unpause_physics``, ``reset_world`` and ``reset_simulation`` (not supported: simulated
time cannot go back here).

Pause. A paused Gazebo world stops its clock: no physics update, no ``/clock``,
so a script's ``rospy.sleep`` (or any call that waits on simulated time) waits
until something unpauses it. Here nothing else can: such a call ends the run
(``ROSInterruptException``, the report's ``shutdown`` says why), as the user's
Ctrl-C ends a script that hangs in the course. Services keep answering while
paused (Gazebo's do).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from omtp_drake.ros.comm._core import (
    LINK_STATES,
    MODEL_STATES,
    GazeboWorld,
    ServiceCallFailed,
    WorldServices,
    gazebo_messages,
    state_publications,
)
from omtp_drake.ros.comm.interfaces import EmptyService
from omtp_drake.ros.comm.messages import Header, Message, Time, Twist, Vector3
from omtp_drake.ros.gazebo.cell_services import Service, ServiceFailure
from omtp_drake.ros.gazebo.interfaces import (
    DeleteModel,
    GetLinkState,
    GetModelState,
    LinkState,
    LinkStates,
    ModelStates,
    SetModelState,
    SpawnModel,
)
from omtp_drake.ros.gazebo.sensor_topics import Source
from omtp_drake.ros.tf.convert import pose_msg, rigid

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("rospy")

__all__ = ["LINK_STATES", "MODEL_STATES", "SET_MODEL_STATE", "GazeboApi", "PushedSource"]

SET_MODEL_STATE = "/gazebo/set_model_state"
#: The layer's states -> this API's message type.
STATE_TYPES = {MODEL_STATES: ModelStates, LINK_STATES: LinkStates}


class PushedSource(Source):
    """A topic the cell publishes by itself into the session (at physics updates, or
    latched): ``poll`` has nothing; its type is known for checks."""

    def __init__(self, msg_class: Any):
        self.msg_class = msg_class

    def poll(self) -> list[tuple[float, Any]]:
        return []


def twist_msg(twist: tuple[float, ...]) -> Message:
    return Twist(Vector3(*twist[:3]), Vector3(*twist[3:]))


def states_msg(states: Any) -> Message:
    """The layer's model or link states as ``gazebo_msgs/ModelStates`` or ``LinkStates``."""
    msg: Any = (LinkStates if isinstance(states, gazebo_messages.LinkStates) else ModelStates)()
    msg.name.extend(states.name)
    msg.pose.extend(pose_msg(X) for X in states.pose)
    msg.twist.extend(twist_msg(t) for t in states.twist)
    return msg


class GazeboApi:
    """Gazebo's ROS API on ``session``'s cell (see the module doc); ``world`` is the plugin
    layer's world the session's plugins share."""

    def __init__(self, session: Graph, world: GazeboWorld):
        self.session = session
        self.cell = session.cell
        self.world = world
        self.models = world.models
        self.api = WorldServices(world)
        self.paused = False
        self._states = state_publications(world, "noetic")

    def publish_states(self, t: float) -> None:
        """The states due at physics update ``t`` (an update hook: after the spawner's, so a
        part spawned at an update is in that update's states)."""
        for publication in self._states:
            if self.session.num_subscribers(publication.topic):
                for states in publication.poll(t):
                    self.session.publish(publication.topic, states_msg(states), t)

    def on_subscribe(self, topic: str) -> None:
        if topic in STATE_TYPES:
            self.world.start_updates()

    def clock_stopped(self) -> Optional[str]:
        """Why simulated time cannot advance now (None: it can)."""
        if not self.paused:
            return None
        return (
            "simulated time stands still: Gazebo's physics is paused (/gazebo/pause_physics) and "
            "nothing else in this run calls /gazebo/unpause_physics (in the course the script waits "
            "for ever)"
        )

    # ------------------------------------------------------------ services

    def get_model_state(self, request: Any) -> Any:
        reply = self.api.get_model_state(request.model_name, request.relative_entity_name)
        response: Any = GetModelState._response_class(
            success=reply.success, status_message=reply.status_message
        )
        if reply.seq:
            response.header = Header(
                seq=reply.seq, stamp=Time(self.cell.time), frame_id=request.relative_entity_name
            )
        if reply.success:
            response.pose, response.twist = pose_msg(reply.X), twist_msg(reply.twist)
        return response

    def get_link_state(self, request: Any) -> Any:
        reply = self.api.get_link_state(request.link_name, request.reference_frame)
        response: Any = GetLinkState._response_class(
            success=reply.success, status_message=reply.status_message
        )
        if reply.success:
            response.link_state = LinkState(
                link_name=request.link_name,
                pose=pose_msg(reply.X),
                twist=twist_msg(reply.twist),
                reference_frame=request.reference_frame,
            )
        return response

    def set_model_state(self, request: Any) -> Any:
        state = request.model_state
        linear, angular = state.twist.linear, state.twist.angular
        reply = self.api.set_model_state(
            state.model_name,
            lambda: rigid(state.pose, "model_state.pose"),
            np.array([linear.x, linear.y, linear.z], dtype=float),
            np.array([angular.x, angular.y, angular.z], dtype=float),
            state.reference_frame,
        )
        return SetModelState._response_class(success=reply.success, status_message=reply.status_message)

    def delete_model(self, request: Any) -> Any:
        reply = self.api.delete_model(request.model_name)
        return DeleteModel._response_class(success=reply.success, status_message=reply.status_message)

    def spawn(self, request: Any, service: str) -> Any:
        try:
            reply = self.api.spawner.spawn(
                service,
                request.model_name,
                request.model_xml,
                rigid(request.initial_pose, "initial_pose"),
                request.reference_frame,
            )
        except ServiceCallFailed as e:
            raise ServiceFailure(str(e)) from None
        return SpawnModel._response_class(success=reply.success, status_message=reply.status_message)

    def reset_world(self, _request: Any) -> Any:
        self.api.spawner.reset_world()
        return EmptyService._response_class()

    def pause(self, on: bool) -> Any:
        self.paused = on
        _log.info("gazebo: physics %s at t = %.3f s", "paused" if on else "running", self.cell.time)
        return EmptyService._response_class()

    def reset_simulation(self, _request: Any) -> Any:
        self.api.reset_simulation("/gazebo/reset_simulation", "/gazebo/reset_world")  # refused

    def services(self) -> list[Service]:
        def spawner(name: str) -> Callable[[Any], Any]:
            return lambda request: self.spawn(request, name)

        spawns = ("/gazebo/spawn_urdf_model", "/gazebo/spawn_sdf_model")
        return [
            Service("/gazebo/get_model_state", GetModelState, self.get_model_state),
            Service("/gazebo/set_model_state", SetModelState, self.set_model_state),
            Service("/gazebo/get_link_state", GetLinkState, self.get_link_state),
            *(Service(name, SpawnModel, spawner(name)) for name in spawns),
            Service("/gazebo/delete_model", DeleteModel, self.delete_model),
            Service("/gazebo/pause_physics", EmptyService, lambda _r: self.pause(True)),
            Service("/gazebo/unpause_physics", EmptyService, lambda _r: self.pause(False)),
            Service("/gazebo/reset_world", EmptyService, self.reset_world),
            Service("/gazebo/reset_simulation", EmptyService, self.reset_simulation),
        ]

    def sources(self) -> dict[str, Source]:
        return {topic: PushedSource(kind) for topic, kind in STATE_TYPES.items()}
