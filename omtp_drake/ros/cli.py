"""The ``ros-run`` and ``grade`` commands (registered with :func:`add_commands`).

``python -m omtp_drake.ros.cli ros-run ...`` runs them without the main CLI.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence
from pathlib import Path

from omtp_drake.errors import OmtpError
from omtp_drake.ros.command import add_shared_options, passed_on, print_line, show_logs
from omtp_drake.ros.report import show_report


def cmd_ros_run(args: argparse.Namespace) -> int:
    """``ros-run``: exit 0 when the script ended cleanly (no exception, no collision)."""
    from omtp_drake.ros.runner import run_script

    if args.sandbox is not None:
        from omtp_drake.ros.grade import run_isolated_script

        return run_isolated_script(args, print_line)
    show_logs(args, "rospy", "moveit_commander")
    report = run_script(
        args.script,
        args.script_args,
        calls=args.call or (),
        **passed_on(
            args,
            "scenario seed timeout moveit meshcat realtime record srdf moveit_config settle latency "
            "settle_after",
        ),
    )
    return show_report(report, args.json, print_line)


def cmd_grade(args: argparse.Namespace) -> int:
    """``grade``: exit 0 when every script ran cleanly."""
    from omtp_drake.ros.grade import OK, grade_folder
    from omtp_drake.ros.grade_flexbe import FlexbeGrading, shared_workspaces
    from omtp_drake.ros.grade_options import class_options
    from omtp_drake.ros.grade_table import format_grades
    from omtp_drake.ros.isolation import limits_from_args

    if (args.workspace or args.python2 or args.behavior) and not args.flexbe:
        raise OmtpError(
            "--workspace, --python2 and --behavior go with --flexbe (a class of FlexBE workspaces)"
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


def _add_ros_run(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """``ros-run``'s parser."""
    from omtp_drake.ros.isolation import add_isolation_flags

    p = sub.add_parser(
        "ros-run",
        help="run an unmodified ROS 1 course script (rospy, MoveIt commander, tf2) in simulated time",
        description="Runs SCRIPT with the ROS names of omtp_drake (rospy, moveit_commander, tf2_ros, "
        "geometry_msgs, omtp_gazebo...) on the scenario's cell, in one process, in simulated time. "
        "Script arguments go right after the script, or after --.",
    )
    p.add_argument("script", metavar="SCRIPT.py")
    p.add_argument("script_args", nargs="*", metavar="SCRIPT_ARGS", help="the script's own arguments")
    add_shared_options(p, "--scenario --seed")
    p.add_argument(
        "--timeout",
        type=float,
        default=600.0,
        metavar="S",
        help="shut the ROS session down after S simulated seconds (default 600)",
    )
    p.add_argument(
        "--moveit",
        choices=["noetic", "melodic"],
        default="noetic",
        help="MoveIt's Python API version: the shape of plan() (default noetic)",
    )
    _add_course_options(p)
    add_shared_options(p, "--meshcat")
    p.add_argument("--realtime", action="store_true", help="pace the simulation at real time")
    add_shared_options(p, "--record --json")
    p.add_argument("-q", "--quiet", action="store_true", help="no rospy/MoveIt log lines")
    p.add_argument("--wall-timeout", type=float, default=900.0, metavar="S", help="wall s (with --sandbox)")
    add_isolation_flags(p, sandbox_default=None)
    p.set_defaults(func=cmd_ros_run)
    return p


def _add_course_options(p: argparse.ArgumentParser) -> None:
    """ros-run's options for the course's set-up: the student's MoveIt config, the slides'
    set-up calls, the time a script's calls take."""
    add_shared_options(p, "--srdf --moveit-config")
    p.add_argument(
        "--call",
        action="append",
        metavar="'SERVICE [ARGS]'",
        help="call SERVICE before the script, as `rosservice call SERVICE ARGS` (ARGS: its YAML, e.g. "
        "'/gripper2/control {enable: true}'); repeat for several, in order",
    )
    p.add_argument(
        "--settle",
        type=float,
        default=0.0,
        metavar="S",
        help="let the cell run S simulated seconds after the calls, before the script (default 0)",
    )
    add_shared_options(p, "--settle-after")
    p.add_argument(
        "--latency",
        default=None,
        metavar="SPEC",
        help="simulated time planning, trajectory starts and service calls take: a factor on the "
        "scenario's ros_latency (0: none, as a cell that stands still while a script thinks) or "
        "NAME=SECONDS,... with names plan, execute, cartesian, service (default: the scenario's)",
    )


def _add_grade(sub: argparse._SubParsersAction, ros_run: argparse.ArgumentParser) -> None:
    """``grade``'s parser: its own flags, the isolation flags, ros-run's options, FlexBE's."""
    from omtp_drake.ros.grade_options import add_grade_flags
    from omtp_drake.ros.isolation import add_isolation_flags

    p = sub.add_parser(
        "grade",
        help="ros-run every script of a folder (submissions) on a scenario: one row per script",
        description="Each script runs isolated (its own copy of the folder, limits, bubblewrap where "
        "it works) on local Dask workers; the table, OUT/grades.csv, OUT/grades.png and each run's "
        "report and output in OUT/runs/.",
    )
    p.add_argument("folder", metavar="DIR")
    add_shared_options(p, "--scenario")
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
        help="with --flexbe: a workspace every behaviour uses (the course's states; repeatable)",
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
    """Registers ``ros-run`` and ``grade`` on the CLI's subparsers."""
    _add_grade(sub, _add_ros_run(sub))


def main(argv: Sequence[str] | None = None) -> int:
    from omtp_drake.ros.guard import install_from_env

    install_from_env()  # an isolated run's limits and guard (omtp_drake.ros.isolation), if it is one
    from omtp_drake.ros.flexbe.cli import add_commands as add_flexbe_commands

    parser = argparse.ArgumentParser(prog="omtp-drake", description="ROS scripts on the OMTP cell.")
    sub = parser.add_subparsers(dest="command", required=True)
    add_commands(sub)
    add_flexbe_commands(sub)  # grade --flexbe runs each behaviour as `flexbe-run` here
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="[%(levelname)s] %(name)s: %(message)s")
    import pydrake.common  # noqa: F401  (sets the drake logger's level first)

    logging.getLogger("drake").setLevel(logging.ERROR)
    try:
        return args.func(args)
    except OmtpError as e:
        sys.stderr.write(f"omtp-drake: error: {e}\n")
        return 2


if __name__ == "__main__":
    sys.exit(main())
