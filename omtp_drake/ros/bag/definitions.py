"""ROS 2 message definitions as a bag's schema carries them: a type's ``.msg`` text followed
by the text of every type it names, each after a line of ``=`` and ``MSG: pkg/Name`` (the
concatenated form rosbag2 and Foxglove read).

A type's own text comes from a :data:`TextSource`: the ``share/<pkg>/msg/<Name>.msg`` files
the ROS 2 message wheels install (:func:`installed_text`), ROS 1 definitions converted
(:mod:`omtp_drake.ros.bag.ros1`), or :data:`NO_PACKAGE` for the types no PyPI wheel ships.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError

#: ``pkg/msg/Name`` -> its ``.msg`` text (None: unknown to the source).
TextSource = Callable[[str], Optional[str]]

#: Field types that name no message.
PRIMITIVES = frozenset(
    "bool byte char float32 float64 int8 uint8 int16 uint16 int32 uint32 int64 uint64 string wstring".split()
)

#: The ROS 2 types of /tf and Gazebo's model and link states (a bag's, and the ROS 2 node's).
TF_MESSAGE = "tf2_msgs/msg/TFMessage"
MODEL_STATES_TYPE = "gazebo_msgs/msg/ModelStates"
LINK_STATES_TYPE = "gazebo_msgs/msg/LinkStates"

#: The ROS 2 types the cell publishes that no PyPI wheel ships (their .msg text, field for field
#: ROS 2's: tf2_msgs, gazebo_msgs; see omtp_drake.ros2.dds_types for their DDS mirrors).
_STATES = "string[] name\ngeometry_msgs/Pose[] pose\ngeometry_msgs/Twist[] twist\n"
NO_PACKAGE: dict[str, str] = {
    TF_MESSAGE: "geometry_msgs/TransformStamped[] transforms\n",
    MODEL_STATES_TYPE: _STATES,
    LINK_STATES_TYPE: _STATES,
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec\n",
    "builtin_interfaces/msg/Duration": "int32 sec\nuint32 nanosec\n",
}


def ros2_name(type_name: str) -> str:
    """``pkg/Name`` or ``pkg/msg/Name`` -> ``pkg/msg/Name``."""
    parts = type_name.split("/")
    return type_name if len(parts) == 3 else f"{parts[0]}/msg/{parts[-1]}"


def field_types(package: str, text: str) -> list[str]:
    """The message types (``pkg/msg/Name``) the fields of ``text`` (a ``.msg`` of ``package``) name."""
    out = []
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        kind = line.split()[0].split("[", 1)[0].split("<=", 1)[0]
        if kind in PRIMITIVES:
            continue
        if kind == "Header":
            kind = "std_msgs/Header"
        out.append(ros2_name(kind if "/" in kind else f"{package}/{kind}"))
    return out


def concatenated(type_name: str, source: TextSource) -> str:
    """The schema text of ``type_name``: its text, then each type it names (depth first, once)."""
    name = ros2_name(type_name)
    seen: dict[str, str] = {}

    def visit(current: str) -> None:
        if current in seen:
            return
        text = source(current)
        if text is None:
            text = NO_PACKAGE.get(current)
        if text is None:
            raise ConfigError(f"no definition of the ROS 2 message {current} (needed by {name})")
        seen[current] = text.strip()
        for dependency in field_types(current.split("/")[0], text):
            visit(dependency)

    visit(name)
    blocks = [seen.pop(name)]
    for dependency, text in seen.items():
        package, _, short = dependency.split("/")
        blocks.append(f"{'=' * 80}\nMSG: {package}/{short}\n{text}")
    return "\n".join(blocks) + "\n"


def share_dirs() -> list[Path]:
    """Where ROS 2 packages' ``share`` folders are: ``AMENT_PREFIX_PATH``'s, then this Python's prefix
    (the message wheels install theirs there)."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    return [Path(p) / "share" for p in [*prefixes, sys.prefix]]


def installed_text(type_name: str) -> Optional[str]:
    """The ``.msg`` text of an installed ROS 2 message package's type (None: not installed)."""
    package, _, short = ros2_name(type_name).split("/")
    for share in share_dirs():
        path = share / package / "msg" / f"{short}.msg"
        if path.is_file():
            return path.read_text()
    return None
