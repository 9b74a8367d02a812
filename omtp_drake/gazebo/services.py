"""What a plugin serves: a service by its name, the neutral request it takes and what it
answers, free of any middleware. A transport gives each service a type of its own (the
course's ``omtp_gazebo`` services under ROS 1, ``std_srvs`` under ROS 2 where the course's
type has no package; docs/ros2.md's table), converts the request to the neutral one, runs
the handler on the cell's thread, between two steps, and converts the reply back.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class ServiceReply:
    """What a plugin answers: ``success`` (every course service's response has it) and a
    line saying what happened (ROS 2's ``std_srvs`` carry it; the course's types drop it)."""

    success: bool
    message: str = ""


@dataclass(frozen=True)
class PluginService:
    """A service of a plugin: its name as gazebo_ros (ROS 1) gives it, the neutral request
    type its handler takes, and the handler (called on the cell's thread)."""

    name: str
    request: type
    handler: Callable[[Any], ServiceReply]
    plugin: str = ""
