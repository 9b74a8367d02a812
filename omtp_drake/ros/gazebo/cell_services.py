"""A service of the cell's ROS 1 graph, and how a handler says it failed.

The services themselves live with what they serve: the plugins' (``/gripperN/control``,
``/omtp/conveyor/control``: :mod:`omtp_drake.gazebo`, given the course's types by
:mod:`omtp_drake.ros.gazebo.plugin_topics`), Gazebo's own (``/gazebo/...``:
:mod:`omtp_drake.ros.gazebo.ros_api`), the spawner's
(:mod:`omtp_drake.ros.gazebo.spawner`) and move_group's (``/compute_ik``...:
:mod:`omtp_drake.ros.moveit.node`).

A service exists only when the scenario has what it drives. A call takes the
session's ``service`` latency before its handler runs (:mod:`omtp_drake.ros.comm.latency`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from omtp_drake.ros.comm.interfaces import ServiceType


class ServiceFailure(Exception):
    """A service handler could not do what was asked (rospy's ServiceException)."""


@dataclass(frozen=True)
class Service:
    """A service of the cell: its type and the handler (request -> response)."""

    name: str
    type: type[ServiceType]
    handler: Callable[[Any], Any]
