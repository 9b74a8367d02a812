"""The course's part spawner on a ROS 1 run: :mod:`omtp_drake.gazebo.spawner`'s services as
``std_srvs/Empty`` services of the session, and its ``/spawned_part`` as a latched
``std_msgs/Header`` topic. The rules (when parts come, what a call that spawns nothing
gets) are the layer's; a call that fails is rospy's ServiceException.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from omtp_drake.errors import OmtpError
from omtp_drake.ros.comm._core import SPAWNED_PART, spawner
from omtp_drake.ros.comm.interfaces import EmptyService as EmptySrv
from omtp_drake.ros.comm.messages import Header, Time
from omtp_drake.ros.gazebo.cell_services import Service, ServiceFailure

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import GazeboWorld
    from omtp_drake.ros.gazebo.graph import Graph

__all__ = ["SPAWNED_PART", "spawner_services"]


def _service(service: Any) -> Service:
    """A spawner's ``std_srvs/Empty`` service (:class:`omtp_drake.gazebo.spawner.EmptyService`)."""

    def handler(_request: Any) -> Any:
        try:
            service.call()
        except OmtpError as e:
            raise ServiceFailure(str(e)) from None
        return EmptySrv._response_class()

    return Service(service.name, EmptySrv, handler)


def spawner_services(session: Graph, world: GazeboWorld) -> list[Service]:
    """The spawner's services of ``session``'s scenario (none without a spawner); its
    ``/spawned_part`` goes out at the physics update of each spawn."""
    found = spawner(world, session.empty_spawn_calls)
    if found is None:
        return []
    if found.publication is not None:
        world.update_hooks.append(_publisher(session, found.publication.poll))
    return [_service(s) for s in found.services]


def _publisher(session: Graph, poll: Callable[[float], list[Any]]) -> Callable[[float], None]:
    def publish(t: float) -> None:
        for m in poll(t):
            header = Header(seq=m.seq, stamp=Time(m.stamp), frame_id=m.frame_id)
            session.latched[SPAWNED_PART] = (m.stamp, -1, header)
            session.publish(SPAWNED_PART, header, m.stamp)

    return publish
