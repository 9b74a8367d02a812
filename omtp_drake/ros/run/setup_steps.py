"""The slides' set-up steps before a script: ``rosservice call`` in a terminal, then wait.

``ros-run --call SERVICE [--call SERVICE ...] --settle S`` calls the services in
order at t = 0, as ``rosservice call`` would, then lets the cell run ``S``
simulated seconds before the script starts. A call is ``NAME`` (a request
without fields: ``std_srvs/Empty``) or ``NAME ARGS`` with ``rosservice call``'s
YAML arguments: a mapping of the request's fields, nested messages as nested
mappings (``'/gripper2/control {enable: true}'``,
``'/omtp/conveyor/control {state: {power: 100}}'``), or the fields in order
(``'/gripper2/control true'``, a YAML list for several). An unknown service, a
bad field or a failed call is a ConfigError, before the script runs.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import yaml

from omtp_drake.errors import ConfigError, check_duration
from omtp_drake.ros.comm.messages import Message
from omtp_drake.ros.comm.names import resolve
from omtp_drake.ros.gazebo.cell_services import ServiceFailure

if TYPE_CHECKING:
    from omtp_drake.ros.comm.session import Session

_log = logging.getLogger("rospy")


def parse_call(text: str) -> tuple[str, Any]:
    """``NAME [ARGS]`` -> (resolved name, the YAML arguments or None)."""
    name, _, args = str(text).strip().partition(" ")
    if not name:
        raise ConfigError("--call needs a service name, e.g. --call /spawn_object_at_robot2")
    try:
        values = yaml.safe_load(args) if args.strip() else None
    except yaml.YAMLError as e:
        raise ConfigError(f"--call {text!r}: its arguments are no YAML: {e}") from None
    return resolve(name, "/rosservice"), values  # a terminal resolves in the global namespace


def fill(msg_class: type[Message], values: Any, what: str) -> Message:
    """A ``msg_class`` message from YAML ``values`` (mapping, list of fields or one field)."""
    if values is None:
        return msg_class()
    names = msg_class.__slots__
    if not isinstance(values, dict):
        values = values if isinstance(values, list) else [values]
        if len(values) > len(names):
            raise ConfigError(f"{what}: {msg_class._type} has {len(names)} fields ({', '.join(names)})")
        values = dict(zip(names, values))
    message = msg_class()
    for key, value in values.items():
        if key not in names:
            raise ConfigError(
                f"{what}: {msg_class._type} has no field {key!r}; fields: {', '.join(names) or 'none'}"
            )
        default = getattr(message, key)
        if isinstance(default, Message):
            value = fill(type(default), value, f"{what}.{key}")
        setattr(message, key, value)
    return message


def call_services(session: Session, calls: Sequence[str]) -> None:
    """Calls each ``--call`` in order, as ``rosservice call`` (no simulated time)."""
    for text in calls:
        name, values = parse_call(text)
        service = session.services.get(name)
        if service is None:
            raise ConfigError(
                f"--call {text!r}: no service {name} in this cell; its services: "
                + ", ".join(sorted(session.services))
            )
        request = fill(service.type._request_class, values, f"--call {name}")
        try:
            response = service.handler(request)
        except ServiceFailure as e:
            raise ConfigError(
                f"--call {text!r}: ERROR: service [{name}] responded with an error: {e}"
            ) from None
        _log.info("--call %s -> %s", name, " ".join(str(response).split()) or "{}")


def settle(session: Session, seconds: float) -> None:
    """Lets the cell run ``seconds`` of simulated time before the script."""
    seconds = check_duration("--settle", seconds, zero=True)
    if session.timeout is not None and seconds >= session.timeout:
        raise ConfigError(f"--settle {seconds:g} s leaves no time of --timeout {session.timeout:g} s")
    if seconds > 0:
        session.run_until(session.time + seconds)
