"""Simulated time that passes while a script's ROS call thinks (planning, a trajectory's
start, a service call), as the course's Gazebo cell runs on meanwhile.

The delays are the scenario's ``ros_latency`` (:class:`~omtp_drake.scenario.latency.RosLatencyConfig`,
where each default comes from); ``ros-run --latency`` overrides them (:func:`resolve_latency`).
A blocking call lets its delay pass with :func:`think` (the cell runs, callbacks are
delivered, the arm stays where it is); a call that returns at once (``go(wait=False)``,
an action goal) starts its motion that much later (:func:`delayed`).
"""

from __future__ import annotations

import copy
import dataclasses
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import RosLatencyConfig, latency_names

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Plan


def resolve_latency(base: RosLatencyConfig, spec: Optional[str | float]) -> RosLatencyConfig:
    """``base`` overridden by ``spec``: None (``base`` as it is), a factor on every delay
    (``0``: calls take no simulated time, ``2``: twice the scenario's), or
    ``NAME=SECONDS[,NAME=SECONDS...]`` with names ``plan``, ``execute``, ``cartesian``,
    ``service``."""
    if spec is None:
        return base
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        return base.scaled(float(spec))
    text = str(spec).strip()
    if "=" not in text:
        try:
            factor = float(text)
        except ValueError:
            raise ConfigError(
                f"--latency {text!r} is neither a factor (0, 1, 2.5...) nor NAME=SECONDS pairs; "
                f"names: {', '.join(latency_names())}"
            ) from None
        return base.scaled(factor)
    values = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        name = name.strip()
        if name not in latency_names():
            raise ConfigError(f"--latency: unknown delay {name!r}; valid: {', '.join(latency_names())}")
        try:
            values[name] = float(value)
        except ValueError:
            raise ConfigError(f"--latency: {name}={value.strip()!r} is not a number of seconds") from None
    latency = dataclasses.replace(base, **values)
    latency.validate()
    return latency


def think(what: str) -> None:
    """Lets the session's ``what`` delay pass (a blocking call's thinking time)."""
    pass_time(delay_of(what))


def pass_time(seconds: float) -> None:
    """Lets ``seconds`` of simulated time pass in a blocking call (the cell runs,
    callbacks are delivered, the arms hold their commands; see ``Session.think``)."""
    from omtp_drake.ros.comm.rostime import _blocking
    from omtp_drake.ros.comm.session import current

    with _blocking():
        current().think(seconds)


def delay_of(what: str) -> float:
    """The session's ``what`` delay [s]."""
    from omtp_drake.ros.comm.session import current

    return float(getattr(current().latency, what))


def delayed(plan: Plan, seconds: float) -> Plan:
    """``plan`` that first holds its start for ``seconds`` (a motion that starts later)."""
    from omtp_drake.ros.comm._core import Plan

    if seconds <= 0:
        return plan
    trajectory = plan.trajectory
    t0 = trajectory.start_time()
    q0 = trajectory.value(t0).ravel()
    held = PiecewisePolynomial.FirstOrderHold([t0, t0 + seconds], np.column_stack([q0, q0]))
    moved = copy.deepcopy(trajectory)
    moved.shiftRight(seconds)
    held.ConcatenateInTime(moved)
    return Plan(held, plan.path, plan.kind, plan.fraction)
