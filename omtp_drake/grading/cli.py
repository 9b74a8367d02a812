"""The ``grade`` command and ``ros-run``'s isolation (``--sandbox``...), registered with
:func:`add_commands` (which registers ``ros-run`` too).

``python -m omtp_drake.grading.cli ros-run ...`` runs them without the main CLI: an
isolated run (:mod:`omtp_drake.grading.isolation`) starts so, its guard first.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import logging
import sys
from collections.abc import Sequence
from pathlib import Path

from omtp_drake.errors import OmtpError
from omtp_drake.launch.options import CommandParser, add_cell_options, resolve_cell_options
from omtp_drake.ros.run.cli import add_commands as add_ros_run
from omtp_drake.ros.run.cli import cmd_ros_run
from omtp_drake.ros.run.command import add_shared_options, passed_on, print_line


def cmd_ros_run_isolable(args: argparse.Namespace) -> int:
    """``ros-run``, isolated when ``--sandbox`` is given."""
    if args.sandbox is not None:
        from omtp_drake.grading.grade import run_isolated_script

        if args.bag:
            raise OmtpError("--bag does not go with --sandbox (an isolated run writes its report only)")

        return run_isolated_script(args, print_line)
    return cmd_ros_run(args)


def cmd_grade(args: argparse.Namespace) -> int:
    """``grade``: exit 0 when every script ran cleanly."""
    from omtp_drake.grading.flexbe import FlexbeGrading, shared_workspaces
    from omtp_drake.grading.grade import OK, grade_folder
    from omtp_drake.grading.isolation import limits_from_args
    from omtp_drake.grading.options import class_options
    from omtp_drake.grading.table import format_grades

    own_files = args.launch or args.world or args.robot  # their --workspace is the cell's
    if ((args.workspace and not own_files) or args.python2 or args.behavior) and not args.flexbe:
        raise OmtpError(
            "--workspace, --python2 and --behavior go with --flexbe (a class of FlexBE workspaces), "
            "--workspace also with --launch, --world or --robot"
        )
    grading = FlexbeGrading(shared_workspaces(args.workspace), args.python2, args.behavior)
    flexbe = grading if args.flexbe else None
    out = args.out or f"grade_{Path(args.folder).resolve().name}"
    grades = grade_folder(
        args.folder,
        args.scenario,
        out=out,
        limits=limits_from_args(args),
        options=class_options(args),
        flexbe=flexbe,
        **passed_on(args, "workers seed timeout wall_timeout sandbox"),
    )
    print_line(format_grades(grades))
    print_line(f"results: {out}/ (runs/*.json, grades.csv, grades.png)")
    return 0 if all(g.status == OK for g in grades) else 1


def _add_isolation(p: argparse.ArgumentParser) -> None:
    """ros-run's flags for an isolated run (as ``grade`` runs each script)."""
    from omtp_drake.grading.isolation import add_isolation_flags

    p.add_argument("--wall-timeout", type=float, default=900.0, metavar="S", help="wall s (with --sandbox)")
    add_isolation_flags(p, sandbox_default=None)
    p.set_defaults(func=cmd_ros_run_isolable)


def _add_grade(sub: argparse._SubParsersAction, ros_run: argparse.ArgumentParser) -> None:
    """``grade``'s parser: its own flags, the isolation flags, ros-run's options, FlexBE's."""
    from omtp_drake.grading.isolation import add_isolation_flags
    from omtp_drake.grading.options import add_grade_flags

    p = sub.add_parser(
        "grade",
        help="ros-run every script of a folder (submissions) on a scenario: one row per script",
        description="Each script runs isolated (its own copy of the folder, limits, bubblewrap where "
        "it works) on local Dask workers; the table, OUT/grades.csv, OUT/grades.png and each run's "
        "report and output in OUT/runs/.",
    )
    p.add_argument("folder", metavar="DIR")
    add_cell_options(p, workspace=False)
    p.set_defaults(cell_file=True)  # each script runs in another process, which loads the cell's file
    p.add_argument("--workers", type=int, default=None, metavar="N", help="worker processes (default: cores)")
    add_shared_options(p, "--seed")
    p.add_argument("--timeout", type=float, default=600.0, metavar="S", help="simulated seconds per script")
    p.add_argument("--wall-timeout", type=float, default=900.0, metavar="S", help="wall seconds per script")
    p.add_argument("--out", default=None, metavar="DIR", help="results folder (default grade_<DIR>)")
    add_isolation_flags(p, sandbox_default="auto")
    add_grade_flags(p, ros_run)
    p.add_argument(
        "--flexbe",
        action="store_true",
        help="DIR holds a catkin workspace per student, each with one FlexBE behaviour (run by flexbe-run)",
    )
    p.add_argument(
        "--workspace",
        action="append",
        default=[],
        metavar="DIR",
        help="with --flexbe: a workspace every behaviour uses (the course's states; repeatable); "
        "with --launch, --world or --robot: where their packages are",
    )
    p.add_argument("--python2", action="store_true", help="with --flexbe: load the workspaces as Python 2")
    p.add_argument(
        "--behavior",
        default="",
        metavar="NAME",
        help="with --flexbe: the behaviour to run where a workspace has several",
    )
    p.set_defaults(func=cmd_grade)


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Registers ``ros-run`` (with its isolation flags) and ``grade`` on the CLI's subparsers."""
    ros_run = add_ros_run(sub)
    _add_isolation(ros_run)
    _add_grade(sub, ros_run)


#: The modules a command's run needs, imported during the start-up (collector off) when it
#: runs a script here rather than isolated elsewhere.
_RUN_MODULES = {"ros-run": "omtp_drake.ros.run.runner", "flexbe-run": "omtp_drake.ros.flexbe.run"}


def main(argv: Sequence[str] | None = None) -> int:
    from omtp_drake.grading.guard import install_from_env

    install_from_env()  # an isolated run's limits and guard (omtp_drake.grading.isolation), if it is one
    # Start-up without the cyclic collector: importing drake, numpy and the simulator makes
    # objects that live as long as the process, and the collections the imports set off find
    # no garbage. A graded run's start took 1.30 instead of 1.41 CPU s (ten alternating
    # pairs). It is on again (and the start-up's objects frozen) before the script runs.
    collecting = gc.isenabled()
    gc.disable()
    try:
        args = _start_up(argv)
    except OmtpError as e:
        sys.stderr.write(f"omtp-drake: error: {e}\n")
        return 2
    finally:
        if argv is None:  # the process's own command line: its modules and scenario live as long as it,
            gc.freeze()  # and the collections of the run skip them
        if collecting:
            gc.enable()
    try:
        return args.func(args)
    except OmtpError as e:
        sys.stderr.write(f"omtp-drake: error: {e}\n")
        return 2


def _start_up(argv: Sequence[str] | None) -> argparse.Namespace:
    """The command line parsed, the cell's options resolved and the run's modules imported."""
    from omtp_drake.ros.flexbe.cli import add_commands as add_flexbe_commands

    parser = CommandParser(prog="omtp-drake", description="ROS scripts on the OMTP cell.")
    sub = parser.add_subparsers(dest="command", required=True)
    add_commands(sub)
    add_flexbe_commands(sub)  # grade --flexbe runs each behaviour as `flexbe-run` here
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="[%(levelname)s] %(name)s: %(message)s")
    import pydrake.common  # noqa: F401  (sets the drake logger's level first)

    logging.getLogger("drake").setLevel(logging.ERROR)
    resolve_cell_options(args, warn=lambda line: sys.stderr.write(f"omtp-drake: warning: {line}\n"))
    if args.command in _RUN_MODULES and getattr(args, "sandbox", None) is None:
        importlib.import_module(_RUN_MODULES[args.command])
    return args


if __name__ == "__main__":
    sys.exit(main())
