"""The ``ros-run`` command (registered with :func:`add_commands`).

:mod:`omtp_drake.grading.cli` adds ros-run's isolation flags (``--sandbox``...) and
``grade``; ``python -m omtp_drake.grading.cli ros-run ...`` runs them without the main CLI.
"""

from __future__ import annotations

import argparse

from omtp_drake.launch.options import add_cell_options
from omtp_drake.ros.run.command import add_shared_options, passed_on, print_line, show_logs
from omtp_drake.ros.run.report import show_report


def cmd_ros_run(args: argparse.Namespace) -> int:
    """``ros-run``: exit 0 when the script ended cleanly (no exception, no collision)."""
    from omtp_drake.ros.run.runner import run_script

    show_logs(args, "rospy", "moveit_commander")
    report = run_script(
        args.script,
        args.script_args,
        calls=args.call or (),
        nodes=args.nodes,
        robot=args.robot,
        workspace=args.workspace or (),
        **passed_on(
            args,
            "scenario seed timeout moveit meshcat realtime record srdf moveit_config settle latency "
            "settle_after bag",
        ),
    )
    return show_report(report, args.json, print_line)


def _add_ros_run(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """``ros-run``'s parser (:mod:`omtp_drake.grading.cli` adds its isolation flags)."""
    p = sub.add_parser(
        "ros-run",
        help="run an unmodified ROS 1 course script (rospy, MoveIt commander, tf2) in simulated time",
        description="Runs SCRIPT with the ROS names of omtp_drake (rospy, moveit_commander, tf2_ros, "
        "geometry_msgs, omtp_gazebo...) on the scenario's cell, in one process, in simulated time. "
        "Script arguments go right after the script, or after --.",
    )
    p.add_argument("script", metavar="SCRIPT.py")
    p.add_argument("script_args", nargs="*", metavar="SCRIPT_ARGS", help="the script's own arguments")
    add_shared_options(p, "--scenario")
    add_cell_options(p)
    p.set_defaults(nodes=[])  # a launch's Python nodes (set with --launch)
    add_shared_options(p, "--seed")
    _add_robot_option(p)
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
    add_shared_options(p, "--realtime")
    add_shared_options(p, "--record --json --bag")
    p.add_argument("-q", "--quiet", action="store_true", help="no rospy/MoveIt log lines")
    p.set_defaults(func=cmd_ros_run)
    return p


def _add_robot_option(p: argparse.ArgumentParser) -> None:
    """``--robot FILE``: a robot spawned as ``spawn_model`` does; with it ``--scenario`` is
    optional (without one: Gazebo's empty world)."""
    p.add_argument(
        "--robot",
        metavar="FILE.urdf[.xacro]|FILE.sdf",
        help="spawn this robot (URDF, xacro or SDF) into the scenario, as spawn_model does; without "
        "--scenario, into Gazebo's empty world (a ground plane)",
    )
    p._option_string_actions["--scenario"].required = False


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
    add_shared_options(p, "--settle-after --latency")


def add_commands(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Registers ``ros-run`` on the CLI's subparsers; returns its parser."""
    return _add_ros_run(sub)
