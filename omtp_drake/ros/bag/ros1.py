"""ROS 1 messages (the shim's, :mod:`omtp_drake.ros.comm.messages`) as their ROS 2 equivalents
in a bag: the same fields, with ROS 2's types.

=========================  ===========================================
ROS 1                      ROS 2
=========================  ===========================================
``pkg/Name``               ``pkg/msg/Name``
``Header`` (seq, stamp,    ``std_msgs/Header`` (stamp, frame_id: ROS 2's
frame_id)                  has no ``seq``)
``time``, ``duration``     ``builtin_interfaces/Time``, ``Duration``
                           (``sec``, ``nanosec``)
``byte``, ``char``         ``int8``, ``uint8`` (ROS 1's meanings)
=========================  ===========================================

The course's own types (``omtp_gazebo/LogicalCameraImage``...) keep their package name: a
bag's schema carries their definition, so Foxglove shows them and ``ros2 bag play`` replays
them where the package is built.
"""

from __future__ import annotations

from typing import Any, Optional

from omtp_drake.ros.bag.definitions import PRIMITIVES, concatenated, ros2_name
from omtp_drake.ros.comm.messages import Message, _TimeBase, message_type

#: ROS 1 built-in types whose ROS 2 spelling differs.
_RENAMED = {
    "time": "builtin_interfaces/Time",
    "duration": "builtin_interfaces/Duration",
    "byte": "int8",
    "char": "uint8",
    "Header": "std_msgs/Header",
}
_ROS2_HEADER = "builtin_interfaces/Time stamp\nstring frame_id\n"


def _ros1_name(type_name: str) -> str:
    package, *_, short = type_name.split("/")
    return f"{package}/{short}"


def ros2_text(type_name: str) -> Optional[str]:
    """The ROS 2 ``.msg`` text of the ROS 1 shim's type (``pkg/msg/Name``; None: no such class)."""
    name = ros2_name(type_name)
    if name == "std_msgs/msg/Header":
        return _ROS2_HEADER
    cls = message_type(_ros1_name(name))
    if cls is None or not cls._definition:
        return None
    package = name.split("/")[0]
    lines = []
    for raw in cls._definition.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        kind, rest = line.split(None, 1)
        base, bracket, suffix = kind.partition("[")
        if base in _RENAMED:
            base = _RENAMED[base]
        elif base not in PRIMITIVES and "/" not in base:
            base = f"{package}/{base}"
        lines.append(f"{base}{bracket}{suffix} {rest}")
    return "\n".join(lines) + "\n"


def ros2_type(message: Message) -> tuple[str, str]:
    """(``pkg/msg/Name``, concatenated ROS 2 definition) of a ROS 1 message."""
    name = ros2_name(message._type)
    return name, concatenated(name, ros2_text)


def ros2_value(value: Any) -> Any:
    """A ROS 1 message's fields as ROS 2's (dicts and lists; times as ``sec``/``nanosec``)."""
    if isinstance(value, Message):
        fields = value.__slots__
        if value._type == "std_msgs/Header":
            fields = ("stamp", "frame_id")
        return {name: ros2_value(getattr(value, name)) for name in fields}
    if isinstance(value, _TimeBase):
        return {"sec": value.secs, "nanosec": value.nsecs}
    if isinstance(value, (list, tuple)):
        return [ros2_value(x) for x in value]
    return value


def stamp_of(message: Any) -> Optional[float]:
    """The message's ``header.stamp`` in seconds (None: it has no header)."""
    header = getattr(message, "header", None) if "header" in getattr(message, "__slots__", ()) else None
    stamp = getattr(header, "stamp", None)
    return stamp.to_sec() if isinstance(stamp, _TimeBase) else None
