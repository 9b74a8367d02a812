"""``ros-run``: an unmodified ROS 1 course script on a cell, in simulated time.

:func:`run_script` builds the scenario's cell and a ROS :class:`Session` on it,
puts the ROS-named packages of ``omtp_drake/ros/shims`` (``rospy``,
``moveit_commander``, ``tf2_ros``, ``geometry_msgs``, ``omtp_gazebo``...) first
on ``sys.path`` for the script only, runs the script as ``__main__`` with its
own arguments, and takes them off again (``sys.path``, ``sys.argv`` and the
ROS module names are restored, so a real ROS installation is never shadowed
outside the run). The run's outcome is a :class:`~omtp_drake.ros.run.report.RosReport`.

The scenario's periodic spawner starts off, as the course's Gazebo world: parts
come when the script (or a ``--call`` before it) asks; see :mod:`omtp_drake.ros.gazebo.spawner`.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import Cell, load_scenario
from omtp_drake.ros.comm.exceptions import ROSInterruptException
from omtp_drake.ros.comm.latency import resolve_latency
from omtp_drake.ros.comm.session import Session, active
from omtp_drake.ros.gazebo.model_topics import unknown_plugins
from omtp_drake.ros.moveit.node import start_move_group
from omtp_drake.ros.run.py2 import python2_imports, run_as_main, script_code
from omtp_drake.ros.run.report import RosReport, describe_script_exception
from omtp_drake.ros.run.settling import SETTLE_AFTER, Settled, check_settle_after, finish
from omtp_drake.ros.run.setup_steps import call_services
from omtp_drake.ros.run.setup_steps import settle as settle_cell
from omtp_drake.scenario import Scenario, with_robot

_log = logging.getLogger(__name__)

#: The folder of the ROS-named packages (put first on sys.path during a run only).
SHIM_DIR = Path(__file__).resolve().parents[1] / "shims"
#: The top-level names it provides.
SHIM_PACKAGES = tuple(sorted(p.name for p in SHIM_DIR.iterdir() if (p / "__init__.py").is_file()))

MOVEIT_VERSIONS = ("noetic", "melodic")


@contextlib.contextmanager
def script_environment(script: Path, args: Sequence[str]) -> Iterator[None]:
    """sys.argv, sys.path (the shims, then the script's folder) and sys.modules set
    for ``script``; all three restored afterwards."""
    saved_argv, saved_path = sys.argv[:], sys.path[:]
    hidden = {n: m for n, m in sys.modules.items() if n.split(".")[0] in SHIM_PACKAGES}
    for name in hidden:
        del sys.modules[name]  # e.g. a real rospy imported before: the script gets ours
    before = set(sys.modules)
    sys.argv = [str(script), *args]
    sys.path[:0] = [str(SHIM_DIR), str(script.parent)]
    try:
        yield
    finally:
        sys.argv, sys.path[:] = saved_argv, saved_path
        folder = str(script.parent) + os.sep
        for name in set(sys.modules) - before:
            top = name.split(".")[0]
            origin = str(getattr(sys.modules[name], "__file__", "") or "")
            # The ROS names, and the script's own modules (not the project's, wherever it is).
            if top in SHIM_PACKAGES or (top != "omtp_drake" and origin.startswith(folder)):
                del sys.modules[name]
        sys.modules.update(hidden)


def run_script(
    script: str | Path,
    args: Sequence[str] = (),
    *,
    scenario: Optional[str | Path] = None,
    robot: Optional[str | Path] = None,
    workspace: Sequence[str | Path] = (),
    seed: Optional[int] = None,
    timeout: Optional[float] = 600.0,
    moveit: str = "noetic",
    meshcat: bool = False,
    realtime: bool = False,
    record: Optional[str | Path] = None,
    srdf: Optional[str | Path] = None,
    moveit_config: Optional[str | Path] = None,
    calls: Sequence[str] = (),
    settle: float = 0.0,
    latency: Optional[str | float] = None,
    nodes: Sequence[tuple[str | Path, Sequence[str]]] = (),
    settle_after: float = SETTLE_AFTER,
) -> RosReport:
    """Runs ``script`` (with ``args``) on ``scenario``'s cell; the run's report.

    ``robot``: a URDF, xacro or SDF file spawned into the scenario (without one, into
    Gazebo's empty world) as ``spawn_model`` does; ``workspace``: its packages' folders.

    ``timeout``: simulated seconds after which the ROS session shuts down
    (``rospy.is_shutdown()`` turns True, blocking calls raise
    ROSInterruptException, ``spin`` returns). ``moveit``: ``noetic`` or ``melodic``
    (the shape of ``plan()``). ``srdf``, ``moveit_config``: a student's SRDF file and
    MoveIt config package (:mod:`omtp_drake.ros.moveit.config`; default: the cell's own).
    ``calls``, ``settle``: the set-up steps before the script (``rosservice call`` of
    each, then ``settle`` simulated seconds; see :mod:`omtp_drake.ros.run.setup_steps`).
    ``nodes``: (file, command line) of the Python nodes a student's launch starts
    (:mod:`omtp_drake.launch`): each runs first, up to its ``rospy.spin()``, and its
    subscribers, timers and services serve the script's run.
    ``latency``: the simulated time planning, execution starts and service calls take
    (:func:`~omtp_drake.ros.comm.latency.resolve_latency`: None for the scenario's
    ``ros_latency``, a factor on it, or ``NAME=SECONDS`` pairs). ``settle_after``: after
    the script, the cell runs on up to this long until its parts rest, and the report's
    ledger is taken then (:mod:`omtp_drake.ros.run.settling`; 0: at the script's end).
    """
    path = Path(script).resolve()
    if not path.is_file():
        raise ConfigError(f"script {str(script)!r} does not exist")
    if moveit not in MOVEIT_VERSIONS:
        raise ConfigError(f"--moveit {moveit!r} is unknown; valid: {', '.join(MOVEIT_VERSIONS)}")
    if timeout is not None and not timeout > 0:
        raise ConfigError(f"--timeout must be > 0 simulated seconds, got {timeout}")
    settle_s = check_settle_after(settle_after)
    loaded = _run_scenario(scenario, robot, workspace, seed)
    delays = resolve_latency(loaded.ros_latency, latency)
    start = time.perf_counter()
    cell = Cell(loaded, auto_spawn=False, meshcat=meshcat, record=record, realtime=realtime)
    session = Session(cell, timeout=timeout, moveit=moveit, latency=delays)
    try:
        start_move_group(session, srdf, moveit_config)
        _start_nodes(nodes, session)
        with active(session):
            call_services(session, calls)
            settle_cell(session, float(settle))
    except Exception:
        cell.close()
        raise
    ending = _run_main(path, args, session)
    settled, replay = finish(session, settle_s)
    return _report(path, session, ending, settled, time.perf_counter() - start, replay)


def _run_scenario(
    scenario: Optional[str | Path],
    robot: Optional[str | Path],
    workspace: Sequence[str | Path],
    seed: Optional[int],
) -> Scenario:
    """The run's scenario: ``scenario`` (or Gazebo's empty world) with ``robot`` in it, seeded ``seed``."""
    loaded = load_scenario(str(scenario)) if scenario is not None else None
    if robot is not None:
        loaded = with_robot(loaded, robot, workspace)
    if loaded is None:
        raise ConfigError("ros-run needs --scenario NAME|FILE or --robot FILE")
    return loaded if seed is None else dataclasses.replace(loaded, seed=int(seed))


@dataclasses.dataclass
class _Ending:
    """How a script's run ended: its exception (None: none), its exit code, Python 2."""

    exception: Optional[BaseException] = None
    exit_code: int = 0
    python2: bool = False


def _run_main(path: Path, args: Sequence[str], session: Session) -> _Ending:
    """Runs the script as ``__main__`` in its environment; how it ended."""
    ending = _Ending()
    try:
        code = script_code(path)
        ending.python2 = code.python2
        # A Python 2 script's own modules (its folder's) load translated too.
        with (
            script_environment(path, args),
            python2_imports([path.parent], code.python2),
            active(session),
            session.threads.running(),  # the script's threads take turns with it
        ):
            run_as_main(code, path)
    except SystemExit as e:
        ending.exit_code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    except ROSInterruptException as e:
        if session.shutdown_reason is None:
            ending.exception = e
    except Exception as e:  # the script's own error: reported, not raised
        ending.exception = e
    return ending


def _start_nodes(nodes: Sequence[tuple[str | Path, Sequence[str]]], session: Session) -> None:
    for node, argv in nodes:
        _start_node(Path(node), argv, session)


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


def _report(
    path: Path, session: Session, ending: _Ending, settled: Settled, wall: float, replay: Optional[Path]
) -> RosReport:
    cell, exception = session.cell, ending.exception
    return RosReport(
        script=path.name,
        scenario=cell.scenario.name,
        seed=cell.scenario.seed,
        sim_time_s=settled.end,
        settle_s=settled.seconds,
        at_rest=settled.at_rest,
        wall_time_s=wall,
        ledger=cell.ledger().to_dict(),
        collisions=list(session.collisions),
        callback_errors=list(session.callback_errors),
        thread_errors=list(session.thread_errors),
        exception=describe_script_exception(exception, path) if exception is not None else None,
        traceback=_script_traceback(exception, path) if exception is not None else [],
        shutdown=session.shutdown_reason,
        exit_code=ending.exit_code,
        python2=ending.python2,
        empty_spawn_calls=list(session.empty_spawn_calls),
        ignored_plugins=unknown_plugins(cell),
        bounds_fixed=list(session.bounds_fixed),
        replay=str(replay) if replay else None,
    )


def _script_traceback(exception: BaseException, script: Path) -> list[str]:
    """``file:line in function: code`` of the traceback's frames in the script's folder."""
    import traceback

    frames = traceback.extract_tb(exception.__traceback__)
    folder = str(script.parent)
    return [
        f"{Path(f.filename).name}:{f.lineno} in {f.name}: {(f.line or '').strip()}"
        for f in frames
        if f.filename.startswith(folder)
    ]
