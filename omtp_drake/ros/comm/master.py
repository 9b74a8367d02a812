"""rosgraph's master API (``rosgraph.Master``, ``rosgraph.masterapi``) and rospy's
``get_published_topics``, answered from the session's graph (:mod:`.graph`).

The master is the run itself: ``is_master_online()`` is true inside a run, the master's
URI is ROS's default, and a call answers what the session's graph holds when it is made.
Only the graph calls that ``rostopic list`` and ``rosnode list`` make are here; any other
master call raises one NotSupportedError naming those.
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.ros.comm import graph
from omtp_drake.ros.comm.exceptions import ROSException
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.comm.unsupported import not_supported

#: ROS's default master URI (``ROS_MASTER_URI``).
MASTER_URI = "http://localhost:11311/"
_CALLS = ("getPublishedTopics", "getSystemState", "getTopicTypes", "getUri", "is_online")


class MasterException(Exception):
    """rosgraph's base of the master's errors."""


class MasterError(MasterException):
    """The master answered with an error (rosgraph's)."""


class MasterFailure(MasterException):
    """The master failed (rosgraph's)."""


class Master:
    """``rosgraph.Master(caller_id)``: the graph of the run's session."""

    def __init__(self, caller_id: str, master_uri: Optional[str] = None):
        if not caller_id:
            raise ValueError("caller_id must be a non-empty string")
        self.caller_id = caller_id
        self.master_uri = master_uri or MASTER_URI

    def is_online(self) -> bool:
        return True

    def getUri(self) -> str:
        return self.master_uri

    def getSystemState(self) -> list[list[list[Any]]]:
        """``[publishers, subscribers, services]``, each ``[[name, [node, ...]], ...]``."""
        return graph.system_state(current())

    def getTopicTypes(self) -> list[list[str]]:
        return graph.topic_types(current())

    def getPublishedTopics(self, subgraph: str) -> list[list[str]]:
        return graph.published_topics(current(), subgraph)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        not_supported(f"rosgraph.Master.{name}", f"the master here answers {', '.join(_CALLS)}")


def is_master_online(master_uri: Optional[str] = None) -> bool:
    """True inside a run (the session is the master)."""
    current()
    return True


def get_master_uri() -> str:
    return MASTER_URI


def get_published_topics(namespace: str = "/") -> list[list[str]]:
    """rospy's ``get_published_topics``: ``[[topic, type], ...]`` published under ``namespace``."""
    if not isinstance(namespace, str):
        raise ROSException(f"namespace must be a string, got {namespace!r}")
    return graph.published_topics(current(), namespace)
