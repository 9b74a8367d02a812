"""What the ROS commands (``ros-run``, ``grade``, ``flexbe-run``) share: the options they
declare alike, their output lines, their log lines while a run goes, and the options they pass
on under their own names."""

from __future__ import annotations

import argparse
import logging
import sys
from typing import Any

from omtp_drake.ros.run.settling import SETTLE_AFTER

#: The options the ROS commands declare alike: flag -> ``add_argument``'s keywords.
SHARED_OPTIONS: dict[str, dict[str, Any]] = {
    "--seed": {"type": int, "default": None, "help": "override the scenario's seed"},
    "--srdf": {
        "metavar": "FILE",
        "help": "the move groups, named states and end effectors of this SRDF (a student's omtp.srdf; "
        "default: the cell's)",
    },
    "--moveit-config": {
        "metavar": "DIR",
        "help": "a MoveIt config package: its config/*.srdf and config/joint_limits.yaml",
    },
    "--meshcat": {"action": "store_true", "help": "show the run in a live Meshcat view"},
    "--realtime": {"action": "store_true", "help": "pace the simulation at real time"},
    "--latency": {
        "default": None,
        "metavar": "SPEC",
        "help": "simulated time planning, trajectory starts and service calls take: a factor on the "
        "scenario's ros_latency (0: none, as a cell that stands still while a script thinks) or "
        "NAME=SECONDS,... with names plan, execute, cartesian, service (default: the scenario's)",
    },
    "--call": {
        "action": "append",
        "metavar": "'SERVICE [ARGS]'",
        "help": "call SERVICE before the run starts, as `rosservice call SERVICE ARGS` (ARGS: its YAML, "
        "e.g. '/gripper2/control {enable: true}'); repeat for several, in order",
    },
    "--settle": {
        "type": float,
        "default": 0.0,
        "metavar": "S",
        "help": "let the cell run S simulated seconds after the calls, before the run starts (default 0)",
    },
    "--record": {"metavar": "HTML", "help": "write a standalone Meshcat replay"},
    "--json": {"metavar": "FILE", "help": "write the run's report as JSON"},
    "--bag": {
        "metavar": "FILE.mcap",
        "help": "record every topic of the run, with its simulated stamps, /tf included, as a ROS 2 bag "
        "(MCAP: ros2 bag play, Foxglove; the ros2 extra)",
    },
    "--settle-after": {
        "type": float,
        "default": SETTLE_AFTER,
        "metavar": "S",
        "help": "after the end, let the cell run on until its parts rest, at most S simulated seconds, "
        f"and take the report then (default {SETTLE_AFTER:g}; 0: at the end)",
    },
}


def add_shared_options(p: argparse.ArgumentParser, flags: str) -> None:
    """Declares the :data:`SHARED_OPTIONS` ``flags`` (space-separated) on ``p``, in that order."""
    for flag in flags.split():
        p.add_argument(flag, **SHARED_OPTIONS[flag])


def print_line(text: str) -> None:
    """One line of the command's output on stdout, flushed at once."""
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def show_logs(args: argparse.Namespace, *loggers: str) -> None:
    """The ``loggers``' INFO lines while the run goes, unless ``-q/--quiet``."""
    if not args.quiet:
        for name in loggers:
            logging.getLogger(name).setLevel(logging.INFO)


def passed_on(args: argparse.Namespace, names: str) -> dict[str, Any]:
    """The options ``names`` (space-separated) of ``args``, as keyword arguments of the same names."""
    return {name: getattr(args, name) for name in names.split()}
