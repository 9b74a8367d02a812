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
        controllers=args.controllers or (),
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
    add_cell_options(p)
    p.set_defaults(nodes=[])  # a launch's Python nodes (set with --launch)
    add_shared_options(p, "--seed")
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
    _add_controllers_option(p)
    add_shared_options(p, "--meshcat")
    add_shared_options(p, "--realtime")
    add_shared_options(p, "--record --json --bag")
    p.add_argument("-q", "--quiet", action="store_true", help="no rospy/MoveIt log lines")
    p.set_defaults(func=cmd_ros_run)
    return p


def _add_controllers_option(p: argparse.ArgumentParser) -> None:
    """``--controllers 'FILE.yaml [NAME ...]'``: rosparam load + controller_manager spawner on the
    robots' gazebo_ros_control."""
    p.add_argument(
        "--controllers",
        action="append",
        metavar="'FILE.yaml [NAME ...]'",
        help="load a controllers YAML (as rosparam load) and start its controllers NAME... (as "
        "controller_manager's spawner; default: all) on the robot's gazebo_ros_control; repeatable",
    )


def _add_course_options(p: argparse.ArgumentParser) -> None:
    """ros-run's options for the course's set-up: the student's MoveIt config, the slides'
    set-up calls, the time a script's calls take."""
    add_shared_options(p, "--srdf --moveit-config")
    add_shared_options(p, "--call --settle --settle-after --latency")


def add_commands(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Registers ``ros-run`` on the CLI's subparsers; returns its parser."""
    return _add_ros_run(sub)
