"""What the ROS commands (``ros-run``, ``grade``, ``flexbe-run``) share: their output lines,
their log lines while a run goes, and the options they pass on under their own names."""

from __future__ import annotations

import argparse
import logging
import sys
from typing import Any


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
