"""A run's cell and ROS session, brought up alike for ``ros-run`` and ``flexbe-run``.

:func:`bring_up` checks the run's options, loads the scenario (with ``--robot`` spawned into
it, or into Gazebo's empty world without one; ``--seed``), builds the cell (``--meshcat``,
``--record``, ``--realtime``; the periodic spawner off, as in the course's Gazebo world) and
the :class:`~omtp_drake.ros.comm.session.Session` on it (``--timeout``, ``--moveit``,
``--latency``), starts MoveIt's ``move_group`` (the student's ``--srdf``,
``--moveit-config``; :mod:`omtp_drake.ros.moveit.node`) and then a launch's Python nodes,
each up to its ``rospy.spin()``. Nothing half-built is left when an option is wrong or a
node fails to start: the cell is closed before the error goes up.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Sequence
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError, check_duration
from omtp_drake.ros.comm._core import Cell, Scenario, load_scenario, spawn_controllers, with_robot
from omtp_drake.ros.comm.latency import resolve_latency
from omtp_drake.ros.comm.session import Session, active
from omtp_drake.ros.moveit.node import start_move_group
from omtp_drake.ros.run.environment import script_environment
from omtp_drake.ros.run.py2 import python2_imports, run_as_main, script_code

_log = logging.getLogger(__name__)

#: The shapes of MoveIt's Python API (``MoveGroupCommander.plan``), by ROS distribution.
MOVEIT_VERSIONS = ("noetic", "melodic")


@dataclasses.dataclass(frozen=True)
class RunSettings:
    """What a run's cell and session are built from: ``ros-run``'s and ``flexbe-run``'s options
    (and the keyword arguments of :func:`~omtp_drake.ros.run.runner.run_script` and
    :func:`~omtp_drake.ros.flexbe.run.run_behavior`), checked once by :func:`bring_up`."""

    #: A Scenario, a scenario name of ``diagrams/`` or a scenario file (None: Gazebo's empty world,
    #: with ``robot``).
    scenario: Optional[Scenario | str | Path] = None
    #: A URDF, xacro or SDF file spawned into the scenario, as ``spawn_model`` does.
    robot: Optional[str | Path] = None
    #: The folders of the robot's packages.
    workspace: Sequence[str | Path] = ()
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
    #: (file, command line) of the Python nodes a student's launch starts (:mod:`omtp_drake.launch`):
    #: each runs first, up to its ``rospy.spin()``, and its subscribers, timers and services
    #: serve the run.
    nodes: Sequence[tuple[str | Path, Sequence[str]]] = ()
    #: ``FILE.yaml [NAME ...]`` each: a controllers YAML loaded (``rosparam load``) and its
    #: controllers started (``controller_manager spawner NAME ...``) on the robot's
    #: ``gazebo_ros_control`` (:mod:`omtp_drake.scenario.ros_control_parse`).
    controllers: Sequence[str] = ()
    #: Record every topic into this ROS 2 bag (``.mcap``; :mod:`omtp_drake.ros.bag.session`).
    bag: Optional[str | Path] = None


def bring_up(settings: RunSettings) -> Session:
    """The session of one run (see the module doc)."""
    if settings.moveit not in MOVEIT_VERSIONS:
        raise ConfigError(f"--moveit {settings.moveit!r} is unknown; valid: {', '.join(MOVEIT_VERSIONS)}")
    timeout = None if settings.timeout is None else check_duration("--timeout", settings.timeout)
    loaded = _scenario(settings)
    delays = resolve_latency(loaded.ros_latency, settings.latency)
    cell = Cell(
        loaded, auto_spawn=False, meshcat=settings.meshcat, record=settings.record, realtime=settings.realtime
    )
    try:
        session = Session(cell, timeout=timeout, moveit=settings.moveit, latency=delays)
        if settings.bag is not None:
            from omtp_drake.ros.bag.session import SessionBag

            session.taps.append(SessionBag(session, settings.bag))
        start_move_group(session, settings.srdf, settings.moveit_config)  # params, named states, services
        for node, argv in settings.nodes:
            _start_node(Path(node), argv, session)
    except Exception:
        cell.close()
        raise
    return session


def _scenario(settings: RunSettings) -> Scenario:
    """The run's scenario: ``scenario`` (or Gazebo's empty world) with ``robot`` in it, seeded."""
    loaded = settings.scenario
    if loaded is not None and not isinstance(loaded, Scenario):
        loaded = load_scenario(str(loaded))
    if settings.robot is not None:
        loaded = with_robot(loaded, settings.robot, settings.workspace)
    if loaded is None:
        raise ConfigError("a run needs --scenario NAME|FILE or --robot FILE (none was given)")
    for spec in settings.controllers:
        loaded = dataclasses.replace(loaded, models=spawn_controllers(loaded.models, spec))
    return loaded if settings.seed is None else dataclasses.replace(loaded, seed=int(settings.seed))


def _start_node(path: Path, argv: Sequence[str], session: Session) -> None:
    """Runs a launch's node as ``__main__`` with its command line, up to its ``spin()``; a
    node that fails to start is a ConfigError naming it (roslaunch would report it died)."""
    code = script_code(path)
    saved = session.node_name, session.names
    session.node_name, session.names, session.starting_node = None, None, True
    try:
        with script_environment(path, argv), python2_imports([path.parent], code.python2), active(session):
            run_as_main(code, path)
    except SystemExit:
        pass
    except Exception as e:
        raise ConfigError(f"node {path} {' '.join(argv)}: failed to start: {type(e).__name__}: {e}") from None
    finally:
        session.node_name, session.names = saved
        session.starting_node = False
    _log.info("node %s started", path.name)
