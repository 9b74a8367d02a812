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

import dataclasses
import logging
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import ConfigError, describe_exception, exception_frames, exception_kind
from omtp_drake.ros.comm._core import unknown_plugins
from omtp_drake.ros.comm.exceptions import ROSInterruptException
from omtp_drake.ros.comm.session import Session, active
from omtp_drake.ros.run.bring_up import RunSettings, bring_up
from omtp_drake.ros.run.environment import script_environment
from omtp_drake.ros.run.py2 import python2_imports, run_as_main, script_code
from omtp_drake.ros.run.report import RosReport
from omtp_drake.ros.run.settling import SETTLE_AFTER, Settled, check_settle_after, finish
from omtp_drake.ros.run.setup_steps import call_services
from omtp_drake.ros.run.setup_steps import settle as settle_cell

_log = logging.getLogger(__name__)


def run_script(
    script: str | Path,
    args: Sequence[str] = (),
    *,
    calls: Sequence[str] = (),
    settle: float = 0.0,
    settle_after: float = SETTLE_AFTER,
    **settings: Any,
) -> RosReport:
    """Runs ``script`` (with ``args``) on a scenario's cell; the run's report.

    ``settings``: the run's cell and session, as :class:`~omtp_drake.ros.run.bring_up.RunSettings`
    names them (``scenario`` or ``robot`` required; ``workspace``, ``seed``, ``timeout``,
    ``moveit``, ``meshcat``, ``realtime``, ``record``, ``srdf``, ``moveit_config``,
    ``latency``, ``nodes``: a student's launch's Python nodes, started before the script and
    serving its run). At ``timeout`` simulated seconds the ROS session shuts down
    (``rospy.is_shutdown()`` turns True, blocking calls raise ROSInterruptException, ``spin``
    returns). ``calls``, ``settle``: the set-up steps before the script (``rosservice call``
    of each, then ``settle`` simulated seconds; see :mod:`omtp_drake.ros.run.setup_steps`).
    ``settle_after``: after the script, the cell runs on up to this long until its parts
    rest, and the report's ledger is taken then (:mod:`omtp_drake.ros.run.settling`; 0: at
    the script's end).
    """
    path = Path(script).resolve()
    if not path.is_file():
        raise ConfigError(f"script {str(script)!r} does not exist")
    settle_s = check_settle_after(settle_after)
    start = time.perf_counter()
    session = bring_up(RunSettings(**settings))
    cell = session.cell
    try:
        with active(session):
            call_services(session, calls)
            settle_cell(session, float(settle))
    except Exception:
        session.close_taps()  # a --bag ends readable with what the set-up published
        cell.close()
        raise
    ending = _run_main(path, args, session)
    settled, replay = finish(session, settle_s)
    return _report(path, session, ending, settled, time.perf_counter() - start, replay)


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


def _report(
    path: Path, session: Session, ending: _Ending, settled: Settled, wall: float, replay: Optional[Path]
) -> RosReport:
    cell = session.cell
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
        shutdown=session.shutdown_reason,
        exit_code=ending.exit_code,
        python2=ending.python2,
        empty_spawn_calls=list(session.empty_spawn_calls),
        ignored_plugins=unknown_plugins(cell.scenario),
        bounds_fixed=list(session.bounds_fixed),
        replay=str(replay) if replay else None,
        timed_out=session.timed_out,
        **_exception_fields(ending.exception, path),
    )


def _exception_fields(exception: Optional[BaseException], script: Path) -> dict[str, Any]:
    """The report's fields of the script's exception: told on one line at its deepest frame in
    the script, the script folder's frames, and what it is as data."""
    if exception is None:
        return {}
    folder = str(script.parent)
    return {
        "exception": describe_exception(exception, lambda f: Path(f).resolve() == script),
        "traceback": exception_frames(exception, lambda f: f.startswith(folder)),
        "error": exception_kind(exception),
    }
