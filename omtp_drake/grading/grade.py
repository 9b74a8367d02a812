"""``grade``: every ROS script of a folder (a class's submissions) run on a scenario, isolated.

Each script is one ``ros-run`` (:func:`grade_one`) on its own copy of the class
folder (the other submissions left out), under the guard and limits of
:mod:`omtp_drake.grading.isolation` and in bubblewrap where it works: a script that
crashes, hangs, floods its output, forks, hogs memory or kills its worker costs
only its own row. Runs go to the workers of the batch machinery's Dask cluster
(:func:`omtp_drake.batch.connect`). The result is one row per script: its
verdict (:mod:`omtp_drake.grading.verdicts`), the parts it put in bins, the ledger,
its times, its exception and what the sandbox refused; written to
``OUT/runs/<script>.json`` (the run's report, its limits and sandbox),
``OUT/runs/<script>.stdout.txt`` / ``.stderr.txt`` (its output, capped),
``OUT/grades.csv`` and ``OUT/grades.png`` (parts in bins and simulated time per script).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import shutil
import tempfile
import uuid
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from omtp_drake.errors import ConfigError, check_duration
from omtp_drake.grading import flexbe as grade_flexbe
from omtp_drake.grading import options as grade_options
from omtp_drake.grading.flexbe import FlexbeGrading
from omtp_drake.grading.isolation import (
    Limits,
    guarded_command,
    kill_session,
    limits_from_args,
    refusals,
    resolve_sandbox,
    run_isolated,
)
from omtp_drake.grading.table import Grade, run_record, write_grades
from omtp_drake.grading.verdicts import (
    COLLISION,
    EXCEPTION,
    OK,
    WORKER_DIED,
    classify,
)

if TYPE_CHECKING:
    pass

_log = logging.getLogger(__name__)

__all__ = [
    "COLLISION",
    "EXCEPTION",
    "OK",
    "Grade",
    "GradeSettings",
    "grade_folder",
    "grade_one",
    "grading_client",
]

#: The run's report, in its folder's copy.
_REPORT = ".omtp_report.json"
#: The most a script's folder may hold: every run copies it (a class's folder, not a home).
_COPY_MAX_FILES, _COPY_MAX_MB = 2000, 200


@dataclass(frozen=True)
class GradeSettings:
    """What every run of a grade shares."""

    scenario: str
    seed: Optional[int] = None
    timeout: float = 600.0
    wall_timeout: float = 900.0
    limits: Limits = field(default_factory=Limits)
    #: ``bwrap`` or ``none`` (resolved by :func:`resolve_sandbox`).
    sandbox: str = "none"
    #: Folders never copied with a script's folder (the results folder, when inside).
    skip: tuple[str, ...] = ()
    #: A FlexBE grade (submissions are workspaces run with flexbe-run); None: scripts.
    flexbe: Optional[FlexbeGrading] = None


def grade_one(
    script: str,
    settings: GradeSettings,
    options: Optional[Mapping[str, str]] = None,
    logs: Optional[str] = None,
    args: Sequence[str] = (),
) -> Grade:
    """One script's ros-run, isolated (a Dask task): on a copy of its folder, its output
    to ``logs/<script>.stdout.txt`` and ``.stderr.txt`` (a folder of its own when None)."""
    path = Path(script)
    root = Path(tempfile.mkdtemp(prefix=f"omtp-grade-{path.stem}-"))
    log_dir = Path(logs) if logs else root
    session_file, root_file = log_dir / f"{path.stem}.session", log_dir / f"{path.stem}.root"
    root_file.write_text(str(root))  # for the client to remove when this worker dies
    try:
        work, guarded, ros_args = _prepare(path, root / "work", settings, args)
        report_path = work / _REPORT
        ros_args += ["--scenario", settings.scenario, "--timeout", str(settings.timeout)]
        ros_args += ["--json", str(report_path), "-q", *grade_options.ros_run_flags(options or {})]
        if settings.seed is not None:
            ros_args += ["--seed", str(settings.seed)]
        shared = [Path(w) for w in (settings.flexbe or FlexbeGrading()).workspaces]
        command, env = guarded_command(
            ros_args, work=work, cwd=work, script=guarded, sandbox=settings.sandbox, limits=settings.limits,
            readable=_readable(settings.scenario) + shared + _option_paths(options or {}),
        )  # fmt: skip
        outcome = run_isolated(
            command,
            env,
            cwd=work,
            limits=settings.limits,
            wall_timeout=settings.wall_timeout,
            logs=(log_dir / f"{path.stem}.stdout.txt", log_dir / f"{path.stem}.stderr.txt"),
            sandbox=settings.sandbox,
            session_file=session_file,
        )
        report = _read_report(report_path)
        tail = _tail(Path(outcome.stderr.path))
    finally:
        shutil.rmtree(root, ignore_errors=True)
        session_file.unlink(missing_ok=True)
        root_file.unlink(missing_ok=True)
    status, message = classify(outcome, report, tail, settings.limits, settings.wall_timeout)
    if status == OK and report is not None and "outcome" in report:  # a behaviour's outcome
        message = f"outcome {report['outcome']}" + (f"; {message}" if message else "")
    refused = refusals(outcome, (report or {}).get("error"), tail)
    isolation = {"sandbox": settings.sandbox, "limits": asdict(settings.limits), **asdict(outcome)}
    isolation["options"] = dict(options or {})
    in_bins = sum(report["ledger"]["in_bin"].values()) if report else 0
    return Grade(path.name, status, in_bins, report, message, refused, isolation)


def _prepare(
    path: Path, dest: Path, settings: GradeSettings, args: Sequence[str]
) -> tuple[Path, Path, list[str]]:
    """The submission copied to ``dest``: (the copy's folder, the file whose code arms the
    guard, the command's arguments before the common ones)."""
    if settings.flexbe is None:
        work = _copy_folder(path, dest, settings.skip)
        return work, work / path.name, ["ros-run", str(work / path.name), *args]
    dest.mkdir(parents=True)
    source, flexbe_args = grade_flexbe.prepare(path, dest, settings.flexbe.behavior)
    return dest, source, flexbe_args + grade_flexbe.flexbe_flags(settings.flexbe)


def _copy_folder(script: Path, dest: Path, skip: Sequence[str] = ()) -> Path:
    """The script's folder copied to ``dest``, without the class's other scripts, grade.yaml,
    a report file and the ``skip`` folders."""
    others = {p.name for p in find_scripts(script.parent)} - {script.name}
    others |= {grade_options.OVERRIDES_FILE, _REPORT}

    def ignore(folder: str, names: list[str]) -> set[str]:
        dropped = {n for n in names if n == "__pycache__" or os.path.join(folder, n) in skip}
        return dropped | (others & set(names) if Path(folder) == script.parent else set())

    shutil.copytree(script.parent, dest, symlinks=True, ignore=ignore)
    return dest


def check_copyable(folder: Path, skip: Sequence[str] = ()) -> None:
    """Raises unless ``folder`` (but ``skip``) is small enough to copy for every run."""
    files, size = 0, 0
    for root, dirs, names in os.walk(folder.resolve()):
        dirs[:] = [d for d in dirs if d != "__pycache__" and os.path.join(root, d) not in skip]
        files += len(names)
        size += sum(os.lstat(os.path.join(root, n)).st_size for n in names)
        if files > _COPY_MAX_FILES or size > _COPY_MAX_MB << 20:
            raise ConfigError(
                f"{str(folder)!r} holds over {_COPY_MAX_FILES} files or {_COPY_MAX_MB} MB, and each run "
                "gets a copy of its script's folder: put the scripts in a folder of their own"
            )


def _readable(scenario: str) -> list[Path]:
    """A scenario file's folder (it may live in /tmp, which the sandbox hides)."""
    path = Path(scenario)
    return [path.resolve().parent] if path.suffix in (".yaml", ".yml") and path.is_file() else []


def _option_paths(options: Mapping[str, Any]) -> list[Path]:
    """The folders of the files an option names (a student's SRDF, MoveIt config), which
    may live in /tmp, which the sandbox hides."""
    paths = [Path(options["srdf"]).parent] if options.get("srdf") else []
    return paths + ([Path(options["moveit_config"])] if options.get("moveit_config") else [])


def _read_report(path: Path) -> Optional[dict[str, Any]]:
    try:
        report = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return report if isinstance(report, dict) and "ledger" in report else None


def _tail(path: Path, limit: int = 2000) -> str:
    """The last lines of a log, as one line."""
    try:
        with open(path, "rb") as f:
            f.seek(max(0, f.seek(0, os.SEEK_END) - limit))
            text = f.read().decode(errors="replace")
    except OSError:
        return ""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return " | ".join(lines[-4:])


def run_isolated_script(args: argparse.Namespace, out: Callable[[str], None]) -> int:
    """``ros-run --sandbox``: one script isolated as in a grade; prints its output (as kept) and
    its verdict, writes ``--json`` as a grade's ``runs/<script>.json``; 0 when the verdict is ok."""
    from omtp_drake.ros.comm._core import load_scenario

    if args.meshcat or args.record or args.realtime:
        raise ConfigError(
            "--sandbox has no network and no place to write a replay: drop --meshcat, --record, --realtime"
        )
    script = Path(args.script)
    if not script.is_file():
        raise ConfigError(f"script {args.script!r} does not exist")
    check_copyable(script.resolve().parent)
    load_scenario(args.scenario)
    mode = resolve_sandbox(args.sandbox)
    scenario = str(Path(args.scenario).resolve()) if Path(args.scenario).is_file() else str(args.scenario)
    prepare_cell(scenario)
    check_duration("--wall-timeout", args.wall_timeout)
    settings = GradeSettings(
        scenario, args.seed, args.timeout, args.wall_timeout, limits_from_args(args), mode
    )
    with tempfile.TemporaryDirectory(prefix="omtp-ros-run-") as logs:
        grade = grade_one(str(script.resolve()), settings, _ros_run_options(args), logs, args.script_args)
        for stream in ("stdout", "stderr"):
            text = Path(logs, f"{script.stem}.{stream}.txt").read_text(errors="replace").rstrip()
            if text:
                out(text)
    out(f"verdict: {grade.status}" + (f": {grade.message}" if grade.message else ""))
    if grade.refused:
        out(f"refused by the sandbox: {grade.refused}")
    if args.json:
        Path(args.json).write_text(json.dumps(run_record(grade), indent=2))
        out(f"result: {args.json}")
    return 0 if grade.status == OK else 1


def _ros_run_options(args: argparse.Namespace) -> dict[str, Any]:
    """The ros-run options given on ``ros-run --sandbox``'s command line, for its isolated run."""
    given = {name: getattr(args, name, None) for name in grade_options.ROS_RUN_OPTIONS}
    given = {k: v for k, v in given.items() if v not in (None, [])}  # a 0 is a value (--settle-after 0)
    return grade_options.check_options(given, "ros-run", Path.cwd())


def find_scripts(folder: str | Path) -> list[Path]:
    path = Path(folder)
    if not path.is_dir():
        raise ConfigError(f"grade needs a folder of scripts, got {str(folder)!r}")
    scripts = sorted(p for p in path.glob("*.py") if not p.name.startswith("_"))
    if not scripts:
        raise ConfigError(f"{str(folder)!r} has no .py scripts")
    return scripts


def grade_folder(
    folder: str | Path,
    scenario: str,
    *,
    workers: Optional[int] = None,
    seed: Optional[int] = None,
    timeout: float = 600.0,
    wall_timeout: float = 900.0,
    out: Optional[str | Path] = None,
    limits: Optional[Limits] = None,
    sandbox: str = "auto",
    options: Optional[Mapping[str, str]] = None,
    flexbe: Optional[FlexbeGrading] = None,
    client: Any = None,
) -> list[Grade]:
    """Every script of ``folder`` on ``scenario``, on ``workers`` local Dask workers (or on
    ``client``'s, one of :func:`grading_client`, shared by several grades);
    the grades in script order (also written to ``out``, see the module doc).

    ``limits`` per run (default :class:`Limits`); ``sandbox``: ``auto``, ``bwrap`` or
    ``none``; ``options``: ros-run options for every script (see
    :mod:`omtp_drake.grading.options`; ``folder/grade.yaml`` overrides them per script).
    ``flexbe``: the submissions are student workspaces run with ``flexbe-run``
    (:mod:`omtp_drake.grading.flexbe`).
    """
    from omtp_drake.ros.comm._core import load_scenario

    scripts = (
        find_scripts(folder) if flexbe is None else grade_flexbe.find_workspaces(folder, flexbe.behavior)
    )
    skip = (str(Path(out).resolve()),) if out is not None else ()
    check_copyable(Path(folder), skip)
    load_scenario(scenario)  # a bad name fails before any worker starts
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ConfigError(f"--workers must be an integer >= 1, got {workers!r}")
    wall_timeout = check_duration("--wall-timeout", wall_timeout)
    limits = limits or Limits()
    limits.check()
    class_values = grade_options.check_options(options or {}, "grade", Path.cwd())
    overrides = grade_options.load_overrides(Path(folder), scripts)
    mode = resolve_sandbox(sandbox)
    scenario_arg = str(Path(scenario).resolve()) if Path(scenario).is_file() else str(scenario)
    prepare_cell(scenario_arg)
    settings = GradeSettings(scenario_arg, seed, timeout, wall_timeout, limits, mode, skip, flexbe)
    per_script = {s.name: grade_options.script_options(s.name, class_values, overrides) for s in scripts}
    if flexbe is not None:
        for name, values in per_script.items():
            grade_flexbe.check_flexbe_options(values, f"grade --flexbe, {name}")
    with tempfile.TemporaryDirectory(prefix="omtp-grade-logs-") as tmp:
        logs = Path(out) / "runs" if out is not None else Path(tmp)
        logs.mkdir(parents=True, exist_ok=True)
        if client is not None:
            grades = _grade_all(scripts, settings, per_script, client, logs)
        else:
            with grading_client(workers) as own:
                grades = _grade_all(scripts, settings, per_script, own, logs)
        if out is not None:
            write_grades(grades, Path(out))
    return grades


def prepare_cell(scenario: str) -> None:
    """Builds the scenario's cell once here, before any run: the model cache (converted
    meshes, stand-ins, the mesh memo) is the simulator's, filled now, and read-only to
    the runs (:func:`~omtp_drake.grading.isolation.guarded_command`)."""
    from omtp_drake.ros.comm._core import Cell, load_scenario

    Cell(load_scenario(scenario), auto_spawn=False).close()


@contextmanager
def grading_client(workers: Optional[int] = None) -> Iterator[Any]:
    """A Dask client of a new local cluster of ``workers`` processes for grades
    (:func:`omtp_drake.batch.connect`), on which a task is never retried: a worker's death
    is its script's verdict. Several grades may share it (``grade_folder(..., client=)``):
    its workers start once."""
    import dask
    import distributed  # noqa: F401  (its config defaults first: dask.config.set would drop them on exit)

    from omtp_drake.ros.comm._core import batch_connect

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), batch_connect(workers) as client:
        yield client


def _grade_all(
    scripts: Sequence[Path],
    settings: GradeSettings,
    per_script: Mapping[str, Mapping[str, Any]],
    client: Any,
    logs: Path,
) -> list[Grade]:
    """The runs on ``client``'s cluster, never more at once than the workers' threads (a worker
    holds only the task it runs); a task whose worker died (or that failed) is its row."""
    from distributed import as_completed

    grades: dict[str, Grade] = {}
    todo = list(scripts)
    try:
        running = as_completed()
        names: dict[str, Path] = {}
        while todo or running.count():
            while todo and running.count() < max(1, sum(client.nthreads().values())):
                s = todo.pop(0)
                key = f"grade-{s.stem}-{uuid.uuid4().hex[:8]}"
                args = (str(s.resolve()), settings, dict(per_script[s.name]), str(logs))
                running.add(client.submit(grade_one, *args, key=key, pure=False))
                names[key] = s
            future = next(running)
            script = names.pop(future.key)
            grades[script.name] = _grade_of(future, script, settings, logs)
            future.release()
    finally:  # interrupted (Ctrl-C): the runs still under way go too
        for s in scripts:
            _clean_up_after(s, logs)
    return [grades[s.name] for s in scripts]


def _clean_up_after(script: Path, logs: Path) -> None:
    """Kills the processes and removes the folder of ``script``'s run if its task could not."""
    session, root = logs / f"{script.stem}.session", logs / f"{script.stem}.root"
    if session.is_file():
        kill_session(int(session.read_text().split()[0]))
        session.unlink()
    if root.is_file():
        shutil.rmtree(root.read_text().strip(), ignore_errors=True)
        root.unlink()


def _grade_of(future: Any, script: Path, settings: GradeSettings, logs: Path) -> Grade:
    from omtp_drake.errors import describe_exception

    try:
        return future.result()
    except Exception as e:  # KilledWorker, or the task's own failure: this script's row only
        from distributed import KilledWorker

        _clean_up_after(script, logs)
        isolation = {"sandbox": settings.sandbox, "limits": asdict(settings.limits)}
        what = "its worker died" if isinstance(e, KilledWorker) else "its grading task failed"
        return Grade(script.name, WORKER_DIED, 0, None, f"{what}: {describe_exception(e)}", "", isolation)
