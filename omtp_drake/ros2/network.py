"""Where the cell's ROS 2 nodes are heard: the DDS domain and the discovery range, and
the middleware itself (rclpy on Fast DDS, the ``ros2`` extra).

ROS 2 finds its peers by DDS discovery in a *domain* (``ROS_DOMAIN_ID``, 0-232 as rclpy
accepts it; above 101 a domain's ports may collide with Linux's ephemeral ports, which
ROS 2's docs warn of, and so does this module, once): nodes of different domains never
hear each other, so each run gets its own (given with ``--domain-id``, else
``ROS_DOMAIN_ID`` from the environment, else one the command chooses and prints).
Discovery stays on this machine's loopback by default
(``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, and ``ROS_LOCALHOST_ONLY=1``, its spelling
before Jazzy); reaching other machines of the same network (``SUBNET``) is the user's
explicit choice (``--network``).

The settings are written to the process environment before rclpy initializes: the
middleware reads them when it creates its participant.
"""

from __future__ import annotations

import functools
import logging
import os
from dataclasses import dataclass
from types import ModuleType
from typing import Optional

from omtp_drake.errors import ConfigError, MissingExtraError

#: The largest domain id rclpy (and DDS's port mapping) accepts.
MAX_DOMAIN_ID = 232
#: The largest domain id whose ports stay below Linux's ephemeral range (the ROS 2 docs' safe range).
SAFE_DOMAIN_ID = 101

#: What installs the middleware: the project's extra.
INSTALL_HINT = 'pip install -e ".[ros2]"'


_log = logging.getLogger(__name__)


@functools.cache
def _warn_ephemeral(domain_id: int) -> None:
    """One warning per domain id above :data:`SAFE_DOMAIN_ID`."""
    _log.warning(
        "ROS_DOMAIN_ID=%d: above %d a domain's DDS ports may collide with Linux's ephemeral ports "
        "(/proc/sys/net/ipv4/ip_local_port_range), as ROS 2's docs warn; 0-%d is safe",
        domain_id,
        SAFE_DOMAIN_ID,
        SAFE_DOMAIN_ID,
    )


@dataclass(frozen=True)
class Ros2Network:
    """The DDS domain and discovery range of a run.

    Attributes:
        domain_id: the ROS 2 domain (0-232).
        subnet: discover peers on the local network too (False: this machine only).
    """

    domain_id: int
    subnet: bool = False

    def __post_init__(self) -> None:
        if not (isinstance(self.domain_id, int) and 0 <= self.domain_id <= MAX_DOMAIN_ID):
            raise ConfigError(
                f"ROS_DOMAIN_ID (--domain-id) must be an integer in 0..{MAX_DOMAIN_ID}, "
                f"got {self.domain_id!r}"
            )
        if self.domain_id > SAFE_DOMAIN_ID:
            _warn_ephemeral(self.domain_id)

    @property
    def discovery_range(self) -> str:
        return "SUBNET" if self.subnet else "LOCALHOST"

    def environment(self) -> dict[str, str]:
        """The variables that put a ROS 2 process (ours or a peer) on this network."""
        return {
            "ROS_DOMAIN_ID": str(self.domain_id),
            "ROS_AUTOMATIC_DISCOVERY_RANGE": self.discovery_range,
            "ROS_LOCALHOST_ONLY": "0" if self.subnet else "1",
        }

    def apply(self) -> None:
        """Writes :meth:`environment` into this process's environment (before rclpy starts)."""
        os.environ.update(self.environment())

    def describe(self) -> str:
        where = "this machine's network" if self.subnet else "this machine only (loopback)"
        return f"ROS_DOMAIN_ID={self.domain_id}, discovery: {where}"


def choose_network(domain_id: Optional[int] = None, *, subnet: bool = False) -> Ros2Network:
    """The run's network: ``domain_id`` if given, else ``ROS_DOMAIN_ID`` from the
    environment, else one from 1..101 picked by this process's id (two runs at once
    on one machine rarely share it; give one to be sure)."""
    if domain_id is None:
        text = os.environ.get("ROS_DOMAIN_ID", "").strip()
        if text:
            try:
                domain_id = int(text)
            except ValueError:
                raise ConfigError(
                    f"ROS_DOMAIN_ID in the environment must be an integer in 0..{MAX_DOMAIN_ID}, got {text!r}"
                ) from None
        else:
            domain_id = 1 + os.getpid() % SAFE_DOMAIN_ID
    return Ros2Network(domain_id, subnet)


def import_rclpy() -> ModuleType:
    """rclpy, or one MissingExtraError naming the extra when it (or its middleware,
    Fast DDS, or a message package) is not installed."""
    try:
        import builtin_interfaces.msg  # noqa: F401
        import geometry_msgs.msg  # noqa: F401
        import rclpy
        import rosgraph_msgs.msg  # noqa: F401
        import sensor_msgs.msg  # noqa: F401
        import std_msgs.msg  # noqa: F401
        import std_srvs.srv  # noqa: F401
        import trajectory_msgs.msg  # noqa: F401
        import visualization_msgs.msg  # noqa: F401
    except ImportError as e:  # a missing wheel, or rclpy without librmw_fastrtps_cpp.so
        raise MissingExtraError(
            f"ROS 2 (rclpy, Fast DDS and the message packages) is not installed: {e}; "
            f"install the project's ros2 extra: {INSTALL_HINT}"
        ) from None
    return rclpy
