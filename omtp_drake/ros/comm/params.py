"""The parameter server's tree over the session's flat store of resolved names.

As on ROS's parameter server, a parameter name is a path in a tree: setting a
dictionary sets one parameter per leaf under that namespace (``/gains`` =
``{"p": 1}`` makes ``/gains/p``), getting a namespace returns its parameters as a
dictionary, and deleting a namespace deletes what is under it. ``/`` is the whole
tree. Names here are resolved ones (see :mod:`omtp_drake.ros.comm.names`).
"""

from __future__ import annotations

from collections.abc import MutableMapping
from typing import Any

from omtp_drake.ros.comm.names import SEP


def _under(params: MutableMapping[str, Any], key: str) -> list[str]:
    """The parameters at ``key`` or below it."""
    prefix = key.rstrip(SEP) + SEP
    return [name for name in params if name == key or name.startswith(prefix)]


def get(params: MutableMapping[str, Any], key: str) -> Any:
    """The value at ``key``: a parameter, or a namespace as a (nested) dictionary.

    Raises:
        KeyError: nothing is set at or below ``key`` (the message lists what is set).
    """
    if key in params:
        return params[key]
    names = _under(params, key)
    if not names:
        raise KeyError(f"parameter {key} is not set; set ones: {', '.join(sorted(params)) or 'none'}")
    tree: dict[str, Any] = {}
    start = len(key.rstrip(SEP)) + 1
    for name in sorted(names):
        *path, leaf = name[start:].split(SEP)
        node = tree
        for part in path:
            node = node.setdefault(part, {})
        node[leaf] = params[name]
    return tree


def put(params: MutableMapping[str, Any], key: str, value: Any) -> None:
    """Sets ``key`` to ``value``, replacing what was at or below it; a dictionary
    becomes a namespace with one parameter per leaf (an empty one, an empty value)."""
    for name in _under(params, key):
        del params[name]
    if isinstance(value, dict) and value:
        for child, child_value in value.items():
            put(params, key.rstrip(SEP) + SEP + str(child), child_value)
    else:
        params[key] = value


def has(params: MutableMapping[str, Any], key: str) -> bool:
    return bool(_under(params, key))


def delete(params: MutableMapping[str, Any], key: str) -> None:
    """Deletes ``key`` and everything under it (KeyError when nothing is there)."""
    names = _under(params, key)
    if not names:
        raise KeyError(f"parameter {key} is not set")
    for name in names:
        del params[name]
