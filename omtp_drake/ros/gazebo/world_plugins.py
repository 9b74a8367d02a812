"""The course world's ROS plugins on a run's graph: Gazebo's own API and the spawner.

:func:`attach_gazebo` is what the session calls once: it adds Gazebo's services and
topics (:mod:`omtp_drake.ros.gazebo.ros_api`) over the plugin layer's world, the spawner
as the scenario's launch file wires it (:mod:`omtp_drake.ros.gazebo.spawner`) and the
Gazebo plugins of the cell (:mod:`omtp_drake.ros.gazebo.plugin_topics`), and holds the
clock while physics is paused.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from omtp_drake.ros.comm._core import GazeboWorld
from omtp_drake.ros.comm.messages import Header
from omtp_drake.ros.gazebo.interfaces import SetModelState
from omtp_drake.ros.gazebo.plugin_topics import attach_plugins
from omtp_drake.ros.gazebo.ros_api import SET_MODEL_STATE, GazeboApi, PushedSource
from omtp_drake.ros.gazebo.ros_control_topics import attach_ros_control
from omtp_drake.ros.gazebo.spawner import SPAWNED_PART, spawner_services

if TYPE_CHECKING:
    from omtp_drake.ros.gazebo.graph import Graph


def attach_gazebo(session: Graph) -> GazeboApi:
    """Gazebo's API and the spawner on ``session``: their services and topics added."""
    world = GazeboWorld(session.cell)
    api = GazeboApi(session, world)
    services = api.services() + spawner_services(session, world)
    world.update_hooks.append(api.publish_states)
    session.services.update({s.name: s for s in services})
    session.sources.update(api.sources())
    spawner = session.cell.scenario.spawner
    if spawner is not None and spawner.start_service:
        session.sources[SPAWNED_PART] = PushedSource(Header)

    def hold_while_paused() -> None:
        reason = api.clock_stopped()
        if reason is not None:
            session.shutdown(reason)
            session.check_running()

    session.cell.on_move_step(hold_while_paused)
    session.gazebo = api  # before subscribing: the session tells Gazebo of each subscription

    def teleport(state: Any) -> None:
        api.set_model_state(SetModelState._request_class(model_state=state))

    # gazebo_ros subscribes to set_model_state too (queue 10): a ModelState published there moves the model.
    session.subscribe(SET_MODEL_STATE, teleport, (), 10)
    attach_plugins(session)
    attach_ros_control(session)
    return api
