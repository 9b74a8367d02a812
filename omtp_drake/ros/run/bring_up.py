"""A run's cell and ROS session, brought up alike for ``ros-run`` and ``flexbe-run``.

:func:`bring_up` checks the run's options, loads the scenario (with ``--seed``), builds the
cell (``--meshcat``, ``--record``, ``--realtime``; the periodic spawner off, as in the
course's Gazebo world) and the :class:`~omtp_drake.ros.comm.session.Session` on it
(``--timeout``, ``--moveit``, ``--latency``), and installs the student's MoveIt config
(``--srdf``, ``--moveit-config``). Nothing half-built is left when an option is wrong:
the cell is closed before the error goes up.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError, check_duration
from omtp_drake.ros.comm._core import Cell, load_scenario
from omtp_drake.ros.comm.latency import resolve_latency
from omtp_drake.ros.comm.session import Session
from omtp_drake.ros.moveit.config import install as install_moveit_config

#: The shapes of MoveIt's Python API (``MoveGroupCommander.plan``), by ROS distribution.
MOVEIT_VERSIONS = ("noetic", "melodic")


@dataclasses.dataclass(frozen=True)
class RunSettings:
    """What a run's cell and session are built from: ``ros-run``'s and ``flexbe-run``'s options
    (and the keyword arguments of :func:`~omtp_drake.ros.run.runner.run_script` and
    :func:`~omtp_drake.ros.flexbe.run.run_behavior`), checked once by :func:`bring_up`."""

    #: A scenario name of ``diagrams/`` or a scenario file.
    scenario: str | Path
    #: Overrides the scenario's seed.
    seed: Optional[int] = None
    #: Simulated seconds after which the session shuts down (None: never).
    timeout: Optional[float] = 600.0
    #: MoveIt's Python API version: the shape of ``plan()`` (:data:`MOVEIT_VERSIONS`).
    moveit: str = "noetic"
    #: Show the run in a live Meshcat view.
    meshcat: bool = False
    #: Pace the simulation at real time.
    realtime: bool = False
    #: Write a standalone Meshcat replay here.
    record: Optional[str | Path] = None
    #: A student's SRDF file and MoveIt config package (:mod:`omtp_drake.ros.moveit.config`).
    srdf: Optional[str | Path] = None
    moveit_config: Optional[str | Path] = None
    #: The simulated time calls take, as :func:`~omtp_drake.ros.comm.latency.resolve_latency`
    #: takes it (None: the scenario's ``ros_latency``).
    latency: Optional[str | float] = None


def bring_up(settings: RunSettings) -> Session:
    """The session of one run (see the module doc)."""
    if settings.moveit not in MOVEIT_VERSIONS:
        raise ConfigError(f"--moveit {settings.moveit!r} is unknown; valid: {', '.join(MOVEIT_VERSIONS)}")
    timeout = None if settings.timeout is None else check_duration("--timeout", settings.timeout)
    loaded = load_scenario(str(settings.scenario))
    if settings.seed is not None:
        loaded = dataclasses.replace(loaded, seed=int(settings.seed))
    delays = resolve_latency(loaded.ros_latency, settings.latency)
    cell = Cell(
        loaded, auto_spawn=False, meshcat=settings.meshcat, record=settings.record, realtime=settings.realtime
    )
    try:
        session = Session(cell, timeout=timeout, moveit=settings.moveit, latency=delays)
        install_moveit_config(session, settings.srdf, settings.moveit_config)  # params, named states
    except Exception:
        cell.close()
        raise
    return session
