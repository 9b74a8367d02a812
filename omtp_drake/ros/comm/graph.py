"""The ROS master's view of a session's graph: who publishes, subscribes to and serves
what, as ``rosmaster`` answers ``getSystemState``, ``getTopicTypes`` and
``getPublishedTopics`` (``rosgraph.Master``, ``rospy.get_published_topics``, and so
``rostopic list`` and ``rosnode list``).

- Publishers: every topic of the cell (its Gazebo plugins and sensors, the spawner's
  ``/spawned_part``; node :data:`GAZEBO_NODE`) and every Publisher of the run's
  scripts (the node that made it).
- Subscribers: every Subscriber of the run's scripts (its node); a topic the cell
  itself listens to (``/gazebo/set_model_state``) under :data:`GAZEBO_NODE`.
- Services: the cell's (Gazebo's, the grippers', the spawner's), under :data:`GAZEBO_NODE`.

Not listed: ``/rosout`` and each node's logger services (the run's log goes to
Python's logging, not to a topic), and nodes that neither publish, subscribe nor serve.
Lists are sorted by name (rosmaster's order is its dicts').
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

#: A :class:`omtp_drake.ros.comm.session.Session` (which imports this module): its
#: ``sources``, ``services``, ``registry`` and ``subscribed_topics()`` are read.
Session = Any

#: The node the cell's own topics and services are listed under.
GAZEBO_NODE = "/gazebo"
#: The caller id of a script that has not called ``init_node`` (rospy's).
UNNAMED = "/unnamed"


@dataclass
class GraphRegistry:
    """The scripts' publishers and subscribers: topic -> node -> ROS type name."""

    publishers: dict[str, dict[str, str]] = field(default_factory=lambda: defaultdict(dict))
    subscribers: dict[str, dict[str, str]] = field(default_factory=lambda: defaultdict(dict))

    def add(self, kind: str, topic: str, node: str | None, data_class: Any) -> None:
        table = self.publishers if kind == "pub" else self.subscribers
        table[topic][node or UNNAMED] = type_name(data_class)

    def remove(self, kind: str, topic: str, node: str | None) -> None:
        table = self.publishers if kind == "pub" else self.subscribers
        table.get(topic, {}).pop(node or UNNAMED, None)
        if topic in table and not table[topic]:
            del table[topic]


def type_name(data_class: Any) -> str:
    """``pkg/Type`` of a message class (rospy's ``_type``)."""
    return str(getattr(data_class, "_type", getattr(data_class, "__name__", "*")))


def _publishers(session: Session) -> dict[str, dict[str, str]]:
    table: dict[str, dict[str, str]] = {
        t: {GAZEBO_NODE: type_name(s.msg_class)} for t, s in session.sources.items()
    }
    for topic, nodes in session.registry.publishers.items():
        table.setdefault(topic, {}).update(nodes)
    return table


def _subscribers(session: Session) -> dict[str, dict[str, str]]:
    table: dict[str, dict[str, str]] = {t: dict(n) for t, n in session.registry.subscribers.items()}
    for topic in session.subscribed_topics():
        table.setdefault(topic, {GAZEBO_NODE: ""})
    return table


def system_state(session: Session) -> list[list[list[Any]]]:
    """``[publishers, subscribers, services]``, each ``[[name, [node, ...]], ...]``."""

    def rows(table: dict[str, dict[str, str]]) -> list[list[Any]]:
        return [[name, sorted(nodes)] for name, nodes in sorted(table.items())]

    services = [[name, [GAZEBO_NODE]] for name in sorted(session.services)]
    return [rows(_publishers(session)), rows(_subscribers(session)), services]


def topic_types(session: Session) -> list[list[str]]:
    """``[[topic, type], ...]`` of every topic with a publisher or a typed subscriber."""
    types: dict[str, str] = {}
    for table in (_subscribers(session), _publishers(session)):
        for topic, nodes in table.items():
            known = [t for t in nodes.values() if t]
            if known:
                types[topic] = known[0]
    return [[topic, kind] for topic, kind in sorted(types.items())]


def published_topics(session: Session, subgraph: str = "") -> list[list[str]]:
    """``[[topic, type], ...]`` of the published topics under ``subgraph`` (rosmaster's
    rule: the namespace with a trailing ``/`` as a prefix)."""
    if subgraph and not subgraph.endswith("/"):
        subgraph += "/"
    return [
        [topic, next(iter(nodes.values()))]
        for topic, nodes in sorted(_publishers(session).items())
        if topic.startswith(subgraph)
    ]
