"""``rostopic``'s look-ups of a topic's type, on the ROS session of the run.

A topic is known when the cell publishes it (its sensors) or a publisher of the
run advertises it; its type is then the cell's message class (a script's
publisher: the class it was made with). Unknown topics answer ``(None, None,
None)``, as ``rostopic`` does for a topic nobody publishes.
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.errors import SimulationError
from omtp_drake.ros.comm.client import resolve_name
from omtp_drake.ros.comm.session import current
from omtp_drake.ros.flexbe.context import current_run


def _msg_class(topic: str) -> Optional[Any]:
    session = current()
    source = session.sources.get(topic)
    if source is not None:
        return source.msg_class
    try:
        publisher = current_run().publishers.get(topic)
    except SimulationError:
        return None  # rostopic in a plain ros-run script: the cell's topics only
    return publisher.data_class if publisher is not None else None


def get_topic_class(topic: str, blocking: bool = False) -> tuple[Optional[Any], Optional[str], None]:
    """``(message class, resolved topic, None)``, or ``(None, None, None)``."""
    name = resolve_name(topic)
    msg_class = _msg_class(name)
    return (msg_class, name, None) if msg_class is not None else (None, None, None)


def get_topic_type(topic: str, blocking: bool = False) -> tuple[Optional[str], Optional[str], None]:
    """``('pkg/Type', resolved topic, None)``, or ``(None, None, None)``."""
    msg_class, name, _ = get_topic_class(topic, blocking)
    return (msg_class._type, name, None) if msg_class is not None else (None, None, None)
