"""ROS graph names as rospy resolves them: one home for topics, services, params and actions.

The rules (ROS 1's, as ``rosgraph.names`` and ``rospy.names`` apply them):

- Canonical form: doubled and trailing slashes are dropped (``omtp//camera/`` ->
  ``omtp/camera``); ``/`` stays ``/``.
- Resolution against the node's caller id ``/<ns>/<node>``: a global name (``/a``) is
  kept; a private name (``~a``) goes under the node (``/<ns>/<node>/a``); a relative
  name (``a``) goes under the node's namespace (``/<ns>/a``).
- Remappings come from the command line: every ``from:=to`` argument whose ``from``
  does not start with one ``_`` (that is a private parameter, ``_rate:=5``). Both
  sides are resolved as names of the node, and a name whose resolved form is a
  remapped one becomes the target. ``__name:=`` renames the node and ``__ns:=`` puts it
  in a namespace (else ``ROS_NAMESPACE``, else the root); other ``__x:=`` arguments
  (``__log``, ``__master``...) are not names.
- ``rospy.myargv`` is the command line without the ``:=`` arguments.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import yaml

SEP = "/"
PRIVATE = "~"
REMAP = ":="
#: The command line's special arguments that are names (others, like ``__log``, are not).
SPECIAL_NAME = "__name"
SPECIAL_NS = "__ns"
#: rospy's caller id before ``init_node``.
UNNAMED = "unnamed"


def canonicalize(name: str) -> str:
    """``name`` without doubled or trailing slashes (``/`` stays ``/``, ``""`` stays ``""``)."""
    if not name or name == SEP:
        return name
    parts = [part for part in name.split(SEP) if part]
    return (SEP if name.startswith(SEP) else "") + SEP.join(parts)


def namespace_of(name: str) -> str:
    """The namespace ``name`` is in, with a trailing slash (``/a/b`` -> ``/a/``, ``/a`` -> ``/``)."""
    name = canonicalize(name)
    return name[: name.rfind(SEP) + 1] or SEP


def _check(name: Any) -> str:
    if not isinstance(name, str):
        raise TypeError(f"a graph name must be a str, got {type(name).__name__} {name!r}")
    name = name.strip()
    if PRIVATE in name[1:]:
        raise ValueError(f"{name!r} is not a valid graph name: '~' may only start a name")
    return name


def resolve(name: str, caller_id: str, remappings: Mapping[str, str] | None = None) -> str:
    """``name`` resolved for the node ``caller_id`` (``/<ns>/<node>``), then remapped.

    An empty name resolves to the node's namespace (rosgraph's rule)."""
    name = _check(name)
    if not name:
        return namespace_of(caller_id)
    name = canonicalize(name)
    if name.startswith(SEP):
        resolved = name
    elif name.startswith(PRIVATE):
        resolved = canonicalize(caller_id + SEP + name[1:])
    else:
        resolved = namespace_of(caller_id) + name
    if remappings and resolved in remappings:
        return remappings[resolved]
    return resolved


def command_line_remaps(argv: Sequence[str]) -> dict[str, str]:
    """The ``from:=to`` arguments of ``argv`` that are remappings or special names
    (private parameters ``_x:=v`` are not), unresolved, in order."""
    mappings: dict[str, str] = {}
    for arg in argv:
        if REMAP not in arg:
            continue
        src, dst = (part.strip() for part in arg.split(REMAP, 1))
        if not src or not dst or (src.startswith("_") and not src.startswith("__")):
            continue
        mappings[src] = dst
    return mappings


def private_params(argv: Sequence[str]) -> dict[str, Any]:
    """The ``_name:=value`` arguments of ``argv`` (values read as YAML, as rospy does)."""
    params: dict[str, Any] = {}
    for arg in argv:
        if REMAP not in arg or not arg.startswith("_") or arg.startswith("__"):
            continue
        key, value = arg[1:].split(REMAP, 1)
        if key:
            params[key] = yaml.safe_load(value) if value else ""
    return params


def strip_remaps(argv: Sequence[str]) -> list[str]:
    """``rospy.myargv``: ``argv`` without the ``:=`` arguments."""
    return [arg for arg in argv if REMAP not in arg]


@dataclass(frozen=True)
class NodeNames:
    """How one node resolves names: its caller id and its resolved remappings.

    Build it with :meth:`from_argv`; ``resolve(name)`` is ``rospy.names.resolve_name``."""

    caller_id: str
    remappings: dict[str, str] = field(default_factory=dict)

    @property
    def namespace(self) -> str:
        """The node's namespace, with a trailing slash (``rospy.get_namespace()``)."""
        return namespace_of(self.caller_id)

    def resolve(self, name: str) -> str:
        return resolve(name, self.caller_id, self.remappings)

    @classmethod
    def from_argv(cls, argv: Sequence[str], node: str = UNNAMED) -> NodeNames:
        """The names of node ``node`` started with command line ``argv`` (``__name``,
        ``__ns`` and the remappings in it; ``ROS_NAMESPACE`` when there is no ``__ns``)."""
        raw = command_line_remaps(argv)
        node = raw.get(SPECIAL_NAME, node).strip(SEP) or UNNAMED
        ns = raw.get(SPECIAL_NS, os.environ.get("ROS_NAMESPACE", SEP))
        ns = canonicalize(ns if ns.startswith(SEP) else SEP + ns)
        caller_id = canonicalize(ns.rstrip(SEP) + SEP + node)
        remappings = {
            resolve(src, caller_id): resolve(dst, caller_id)
            for src, dst in raw.items()
            if not src.startswith("__")
        }
        return cls(caller_id, remappings)
