"""``flexbe-run``: a FlexBE behaviour of catkin workspaces on a cell, in simulated time.

:func:`run_behavior` builds the scenario's cell and a ROS session on it (with the
course cell's extra topics, ``/robot_description`` and
``/robot_description_semantic``), puts the ROS-named shims (``rospy``,
``flexbe_core``, ``flexbe_states``, ``rospkg``...) and the workspaces' package
``src`` folders first on ``sys.path`` for the run only, builds the behaviour as
FlexBE's onboard engine does (its class, ``--param`` values, ``create()``), and
spins its state machine in simulated time until it returns an outcome.

A headless run stops, and the report says why, when a state raises, when an
outcome needs an operator (autonomy), or at ``--timeout`` simulated seconds.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import os
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import (
    ConfigError,
    describe_exception,
    exception_frames,
    exception_kind,
    exception_place,
)
from omtp_drake.ros.comm._core import unknown_plugins
from omtp_drake.ros.comm.exceptions import ROSInterruptException
from omtp_drake.ros.comm.session import Session, ShutdownError, active
from omtp_drake.ros.flexbe.context import (
    AUTONOMY_LEVELS,
    FlexbeRun,
    OperatorRequired,
    SessionClock,
    StateFailed,
    active_run,
)
from omtp_drake.ros.flexbe.report import FlexbeReport
from omtp_drake.ros.flexbe.workspace import BehaviorEntry, Workspaces
from omtp_drake.ros.run.bring_up import RunSettings, bring_up
from omtp_drake.ros.run.environment import SHIM_DIR, SHIM_PACKAGES
from omtp_drake.ros.run.py2 import python2_imports, python2_roots
from omtp_drake.ros.run.settling import SETTLE_AFTER, Settled, check_settle_after, finish
from omtp_drake.ros.run.setup_steps import call_services
from omtp_drake.ros.run.setup_steps import settle as settle_cell

#: The node FlexBE's onboard engine runs behaviours in.
ONBOARD_NODE = "behavior_onboard"


@contextlib.contextmanager
def workspace_environment(paths: Sequence[Path]) -> Iterator[None]:
    """sys.path (the shims, then ``paths``) and sys.modules set for a run; both restored."""
    saved_path = sys.path[:]
    hidden = {n: m for n, m in sys.modules.items() if n.split(".")[0] in SHIM_PACKAGES}
    for name in hidden:
        del sys.modules[name]
    before = set(sys.modules)
    sys.path[:0] = [str(SHIM_DIR), *(str(p) for p in paths)]
    folders = tuple(str(p) + os.sep for p in paths)
    try:
        yield
    finally:
        sys.path[:] = saved_path
        for name in set(sys.modules) - before:
            origin = str(getattr(sys.modules[name], "__file__", "") or "")
            if name.split(".")[0] in SHIM_PACKAGES or origin.startswith(folders):
                del sys.modules[name]
        sys.modules.update(hidden)


@contextlib.contextmanager
def genpy_module_names() -> Iterator[None]:
    """For the run, each shim message class's ``__module__`` is genpy's ``pkg.msg._Type``
    (FlexBE's states find a message class by a topic's type that way); restored after."""
    renamed: dict[type, str] = {}
    for package in SHIM_PACKAGES:
        if not (SHIM_DIR / package / "msg.py").is_file():
            continue
        module = importlib.import_module(f"{package}.msg")
        for name in getattr(module, "__all__", []):
            cls = getattr(module, name)
            if isinstance(cls, type) and getattr(cls, "_type", "") == f"{package}/{name}":
                renamed.setdefault(cls, cls.__module__)
                cls.__module__ = f"{package}.msg._{name}"
    try:
        yield
    finally:
        for cls, module_name in renamed.items():
            cls.__module__ = module_name


def parse_params(items: Sequence[str]) -> dict[str, str]:
    """``NAME=VALUE`` pairs (``--param``) as a dict."""
    params = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise ConfigError(f"--param takes NAME=VALUE, got {item!r}")
        params[name.strip()] = value
    return params


def _build(entry: BehaviorEntry, params: dict[str, str]) -> Any:
    """The behaviour's top-level state machine, built as FlexBE's onboard engine does."""
    module = importlib.import_module(entry.module)
    cls = getattr(module, entry.class_name, None)
    if cls is None:
        raise ConfigError(f"{entry.module} has no class {entry.class_name!r} (named in {entry.manifest})")
    behavior = cls()
    for name, value in params.items():
        if not behavior.set_parameter(name, value):
            known = ", ".join(behavior.parameter_names()) or "none"
            raise ConfigError(f"--param {name}: the behaviour has no such parameter; its parameters: {known}")
    machine = behavior.prepare_for_execution()
    machine.confirm(behavior.name)
    return machine


@dataclasses.dataclass
class _Outcome:
    outcome: Optional[str] = None
    error: Optional[BaseException] = None
    failed_state: Optional[str] = None
    #: The workspaces loaded as their Python 2 translation.
    python2: list[str] = dataclasses.field(default_factory=list)


def _spin(entry: BehaviorEntry, params: dict[str, str], session: Session) -> _Outcome:
    result = _Outcome()
    machine = None
    try:
        machine = _build(entry, params)
        result.outcome = machine.spin()
    except StateFailed as e:
        if not isinstance(e.error, ShutdownError):
            result.error, result.failed_state = e.error, e.path
    except (ShutdownError, ROSInterruptException):
        if session.shutdown_reason is None:
            result.error = RuntimeError("the ROS session was interrupted")
    except (OperatorRequired, Exception) as e:
        result.error = e
    finally:
        if machine is not None:
            with contextlib.suppress(Exception):
                machine.destroy()
    return result


def run_behavior(
    behavior: str,
    workspaces: Sequence[str | Path],
    *,
    autonomy: str = "full",
    params: Optional[dict[str, str]] = None,
    python2: bool = False,
    settle_after: float = SETTLE_AFTER,
    calls: Sequence[str] = (),
    settle: float = 0.0,
    **settings: Any,
) -> FlexbeReport:
    """Runs ``behavior`` (a manifest name or a ``*_sm.py`` path) of ``workspaces`` on a
    scenario's cell; the run's report (see the module doc). The cell and its ROS session
    come up as ``ros-run``'s do, from ``settings``
    (:class:`~omtp_drake.ros.run.bring_up.RunSettings`: ``scenario`` or ``robot`` required;
    ``srdf``, ``moveit_config``, ``timeout``, ``seed``, ``meshcat``, ``realtime``, ``record``,
    ``latency``, a launch's ``nodes``...). A workspace with a module that compiles only as
    Python 2 loads converted from Python 2 (:func:`~omtp_drake.ros.run.py2.python2_roots`);
    ``python2``: every workspace does. ``settle_after``: after the outcome, the cell runs on
    up to this long until its parts rest, and the report's ledger is taken then
    (:mod:`omtp_drake.ros.run.settling`). ``calls``, ``settle``: the set-up steps before the
    behaviour starts, as ``ros-run``'s (:mod:`omtp_drake.ros.run.setup_steps`)."""
    if autonomy not in AUTONOMY_LEVELS:
        raise ConfigError(f"--autonomy {autonomy!r} is unknown; valid: {', '.join(AUTONOMY_LEVELS)}")
    settle_s = check_settle_after(settle_after)
    run_settings = RunSettings(**settings)
    spaces = Workspaces(workspaces)
    entry = spaces.find(behavior)
    converted = list(spaces.roots) if python2 else python2_roots(spaces.roots)
    start = time.perf_counter()
    session = bring_up(run_settings)
    try:
        with active(session):
            call_services(session, calls)
            settle_cell(session, float(settle))
    except Exception:
        session.cell.close()
        raise
    session.node_name = ONBOARD_NODE
    run = FlexbeRun(SessionClock(session), autonomy=AUTONOMY_LEVELS[autonomy], packages=dict(spaces.packages))
    with (
        workspace_environment(spaces.python_paths()),
        python2_imports(converted, bool(converted)),
        genpy_module_names(),
        active(session),
        active_run(run),
        session.threads.running(),  # threads a state starts take turns with the engine
    ):
        result = _spin(entry, params or {}, session)
    result.python2 = [str(r) for r in converted]
    settled, replay = finish(session, settle_s)
    return _report(
        entry.name, autonomy, session, run, result, spaces.roots, settled, time.perf_counter() - start, replay
    )


def _report(
    behavior: str,
    autonomy: str,
    session: Session,
    run: FlexbeRun,
    result: _Outcome,
    roots: Sequence[Path],
    settled: Settled,
    wall: float,
    replay: Optional[Path],
) -> FlexbeReport:
    cell, error = session.cell, result.error
    return FlexbeReport(
        behavior=behavior,
        scenario=cell.scenario.name,
        seed=cell.scenario.seed,
        autonomy=autonomy,
        outcome=result.outcome,
        sim_time_s=settled.end,
        settle_s=settled.seconds,
        at_rest=settled.at_rest,
        python2=result.python2,
        wall_time_s=wall,
        ledger=cell.ledger().to_dict(),
        trace=[t.to_dict() for t in run.trace],
        logs=[line.to_dict() for line in run.logs],
        collisions=list(session.collisions),
        callback_errors=list(session.callback_errors),
        thread_errors=list(session.thread_errors),
        exception=describe_error(error, roots) if error is not None else None,
        failed_state=result.failed_state,
        traceback=exception_frames(error, lambda f: _in_roots(f, roots)) if error is not None else [],
        error=exception_kind(error) if error is not None else None,
        timed_out=session.timed_out,
        shutdown=session.shutdown_reason,
        ignored_plugins=unknown_plugins(cell.scenario),
        bounds_fixed=list(session.bounds_fixed),
        replay=str(replay) if replay else None,
    )


def _in_roots(filename: str, roots: Sequence[Path]) -> bool:
    return any(filename.startswith(str(r) + os.sep) for r in roots)


def describe_error(error: BaseException, roots: Sequence[Path]) -> str:
    """``Type: message (at file.py:LINE in function)``: the deepest workspace frame (or,
    for a syntax error, the file and line that do not compile), with what to do about
    a Python 2 module or a missing package."""
    where, hint = exception_place(error, lambda f: _in_roots(f, roots)), ""
    if isinstance(error, SyntaxError) and error.filename:
        where = f" (at {Path(error.filename).name}:{error.lineno}, imported from{where.removeprefix(' (at')}"
        if _in_roots(error.filename, roots):
            hint = "; it compiles neither as Python 3 nor, through 2to3, as Python 2 (ROS Melodic)"
    if isinstance(error, ModuleNotFoundError) and error.name:
        hint = (
            f"; neither the workspaces' packages nor omtp-drake's ROS packages "
            f"({', '.join(SHIM_PACKAGES)}) provide {error.name.split('.')[0]!r}: add the catkin src "
            "folder that holds it with --workspace"
        )
    return describe_exception(error, place=where, hint=hint)
