"""What the cell's ROS plugins (Gazebo's API, the spawner) use of a run's ROS graph.

:class:`~omtp_drake.ros.comm.session.Session` is the graph; the plugins know it only
through this protocol, so they never import the session that attaches them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Optional, Protocol

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell
    from omtp_drake.ros.gazebo.cell_services import Service
    from omtp_drake.ros.gazebo.sensor_topics import Source


class Graph(Protocol):
    """The services, topics and clock of one script's run on ``cell``."""

    cell: Cell
    services: dict[str, Service]
    sources: dict[str, Source]
    #: topic -> (stamp, order, message) of its last latched message.
    latched: dict[str, Any]
    #: Spawner calls that spawned nothing (each logged once).
    empty_spawn_calls: list[str]
    #: The Gazebo world attached to it (omtp_drake.ros.gazebo.ros_api.GazeboApi).
    gazebo: Any

    def num_subscribers(self, topic: str) -> int: ...

    def publish(self, topic: str, message: Any, stamp: Optional[float] = None) -> None: ...

    def subscribe(
        self, topic: str, callback: Callable[..., Any], callback_args: tuple, queue_size: Optional[int]
    ) -> Any: ...

    def check_running(self) -> None: ...

    def shutdown(self, reason: str) -> None: ...
