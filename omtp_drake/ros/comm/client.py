"""rospy's client (``rospy.client``, ``rospy.core``): the node, its names, shutdown,
``spin``, the parameter server and logging, on the current session.

The names and call shapes are rospy's; see :mod:`omtp_drake.ros.comm.session` for how
time and callbacks run. Topics are :mod:`omtp_drake.ros.comm.topics`, services
:mod:`omtp_drake.ros.comm.service`, time :mod:`omtp_drake.ros.comm.rostime`, name rules
:mod:`omtp_drake.ros.comm.names`.
"""

from __future__ import annotations

import copy
import logging
import math
import sys
from collections.abc import Callable
from typing import Any, Optional

from omtp_drake.ros.comm import names, params
from omtp_drake.ros.comm.exceptions import ROSException
from omtp_drake.ros.comm.session import ShutdownError, current

_log = logging.getLogger("rospy")


def init_node(
    name: str, anonymous: bool = False, log_level: Any = None, disable_signals: bool = False, **_: Any
) -> None:
    """Names the node (once per script: a second call with another name raises ROSException).

    The command line (``sys.argv``) may rename it (``__name:=``), put it in a namespace
    (``__ns:=``), remap names (``from:=to``) and set its private parameters (``_x:=v``).
    An anonymous node keeps its name (rospy would append a unique suffix)."""
    session = current()
    name = str(name).strip("/")
    if not name or "/" in name:
        raise ValueError(f"init_node needs a base name without '/', got {name!r}")
    if session.node_name is not None and session.node_name != name:
        raise ROSException(
            "rospy.init_node() has already been called with different arguments: " + session.node_name
        )
    first = session.node_name is None
    session.node_name = name
    session.names = names.NodeNames.from_argv(sys.argv[1:], name)
    if first:
        for key, value in names.private_params(sys.argv[1:]).items():
            params.put(session.params, session.names.resolve(names.PRIVATE + key), value)
    _log.info("node %s up at t = %.3f s (simulated time)", session.names.caller_id, session.time)


def _node_names() -> names.NodeNames:
    """The running node's names (before ``init_node``: rospy's unnamed node's)."""
    session = current()
    return session.names if session.names is not None else names.NodeNames.from_argv(sys.argv[1:])


def resolve_name(name: str, caller_id: Optional[str] = None) -> str:
    """``name`` resolved for this node (or for ``caller_id``) with the command line's remappings."""
    node = _node_names()
    if caller_id is None:
        return node.resolve(name)
    return names.resolve(name, caller_id, node.remappings)


def get_name() -> str:
    return _node_names().caller_id


def get_caller_id() -> str:
    return get_name()


def get_namespace() -> str:
    return _node_names().namespace


def myargv(argv: Optional[list[str]] = None) -> list[str]:
    """``argv`` (default ``sys.argv``) without the remapping arguments."""
    return names.strip_remaps(sys.argv if argv is None else argv)


def is_shutdown() -> bool:
    return current().poll_shutdown()


def signal_shutdown(reason: str) -> None:
    current().shutdown(f"signal_shutdown: {reason}")


def on_shutdown(hook: Callable[[], Any]) -> None:
    current().on_shutdown(hook)


def spin() -> None:
    """Runs the callbacks until shutdown (``signal_shutdown`` or ``--timeout``); a launch's
    node that is starting returns at once (its callbacks run as the script runs)."""
    session = current()
    if session.starting_node:
        return
    try:
        session.run_until(math.inf)
    except ShutdownError:
        return


# ----------------------------------------------------------------------------- parameters


def get_param(name: str, default: Any = KeyError) -> Any:
    """The parameter (or namespace, as a dictionary) at ``name``, a copy as from the
    parameter server; ``default`` when nothing is set there (else KeyError)."""
    key = resolve_name(name)
    try:
        return copy.deepcopy(params.get(current().params, key))
    except KeyError:
        if default is KeyError:
            raise
        return default


def set_param(name: str, value: Any) -> None:
    params.put(current().params, resolve_name(name), copy.deepcopy(value))


def has_param(name: str) -> bool:
    return params.has(current().params, resolve_name(name))


def delete_param(name: str) -> None:
    params.delete(current().params, resolve_name(name))


# ----------------------------------------------------------------------------- logging


def _emit(level: int, msg: Any, args: tuple) -> None:
    text = str(msg) % args if args else str(msg)
    _log.log(level, "[%s] [t=%.3f] %s", get_name(), current().time, text)


def logdebug(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.DEBUG, msg, args)


def loginfo(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.INFO, msg, args)


def logwarn(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.WARNING, msg, args)


def logerr(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.ERROR, msg, args)


def logfatal(msg: Any, *args: Any, **_: Any) -> None:
    _emit(logging.CRITICAL, msg, args)


logout = loginfo
logerror = logerr
logwarning = logwarn


def _throttled(level: int) -> Callable[..., None]:
    def log(period: float, msg: Any, *args: Any) -> None:
        session = current()
        key = (level, str(msg))
        last = session.throttle.get(key)
        if last is None or session.time - last >= float(period):
            session.throttle[key] = session.time
            _emit(level, msg, args)

    return log


loginfo_throttle = _throttled(logging.INFO)
logwarn_throttle = _throttled(logging.WARNING)
logerr_throttle = _throttled(logging.ERROR)
logdebug_throttle = _throttled(logging.DEBUG)


def _once(level: int) -> Callable[..., None]:
    """``log*_once``: ``log*_throttle`` with a period that never ends (and its record of the
    messages logged at ``level``)."""
    throttled = _throttled(level)

    def log(msg: Any, *args: Any) -> None:
        throttled(math.inf, msg, *args)

    return log


loginfo_once = _once(logging.INFO)
logwarn_once = _once(logging.WARNING)
logerr_once = _once(logging.ERROR)
