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

import contextlib
import functools
import logging
import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Optional

from omtp_drake.errors import ConfigError, MissingExtraError

#: The largest domain id rclpy (and DDS's port mapping) accepts.
MAX_DOMAIN_ID = 232
#: The largest domain id whose ports stay below Linux's ephemeral range (the ROS 2 docs' safe range).
SAFE_DOMAIN_ID = 101

#: Fast DDS's participant profile for the cell (:func:`cell_participant_profile`).
FASTDDS_PROFILE = Path(__file__).with_name("fastdds_profile.xml")
#: The variable Fast DDS reads its default profile from (once per process).
PROFILE_VARIABLE = "FASTDDS_DEFAULT_PROFILES_FILE"

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


@contextlib.contextmanager
def cell_participant_profile() -> Iterator[None]:
    """While the block creates the cell's rclpy participant, Fast DDS's default profile is
    :data:`FASTDDS_PROFILE`: ``fastdds.type_propagation`` disabled, so the cell's endpoints
    announce no XTypes type information and its participant serves no TypeLookup. A peer then
    matches the cell's topics by type name, as ROS 2 matched before XTypes, and never asks the
    cell for a type.

    Why: a Fast DDS 3.2 peer that discovers an endpoint of a type it does not hold yet (a node
    starting: its publishers come after its participant) asks for the type, and its TypeLookup
    request reaches every participant of the domain. The cell has two (rclpy's Fast DDS and
    Cyclone DDS, :mod:`omtp_drake.ros2.dds_types`), and both answered. The peer takes the first
    reply; Cyclone's held only the nested types Cyclone shares with ROS (``std_msgs/Header``,
    ``builtin_interfaces/Time``), so the peer dropped the request ("Inconsistent TypeObject")
    and never matched any of the cell's topics with a Header (``/joint_states``,
    ``/set_joint_trajectory``, the cameras): measured in 4 of 12 starts right after the cell.
    Also the cell's Fast DDS answered lookups of Cyclone's types, the red
    ``TYPELOOKUP_SERVICE_REPLY_LISTENER`` lines of every peer.

    Fast DDS reads the profile once per process, at its first participant; the variable is
    restored after the block, so the nodes a launch starts do not inherit it. A profile of the
    user's own (the variable already set) is kept, with one warning.
    """
    own = os.environ.get(PROFILE_VARIABLE)
    if own is not None:
        _log.warning(
            "%s=%s is kept for the cell's participant; unless it sets fastdds.type_propagation to "
            "disabled (as %s does), a node starting beside the cell may never match its topics",
            PROFILE_VARIABLE,
            own,
            FASTDDS_PROFILE,
        )
        yield
        return
    os.environ[PROFILE_VARIABLE] = str(FASTDDS_PROFILE)
    try:
        yield
    finally:
        os.environ.pop(PROFILE_VARIABLE, None)


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
