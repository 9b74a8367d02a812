"""The ``flexbe-run`` command (registered with :func:`add_commands`)."""

from __future__ import annotations

import argparse

from omtp_drake.launch.options import add_cell_options
from omtp_drake.ros.flexbe.context import AUTONOMY_LEVELS
from omtp_drake.ros.run.command import add_shared_options, passed_on, print_line, show_logs
from omtp_drake.ros.run.report import show_report


def cmd_flexbe_run(args: argparse.Namespace) -> int:
    """``flexbe-run``: exit 0 when the behaviour reached an outcome cleanly."""
    from omtp_drake.ros.flexbe.run import parse_params, run_behavior

    show_logs(args, "flexbe", "rospy", "moveit_commander")
    report = run_behavior(
        args.behavior,
        args.workspace,
        params=parse_params(args.param),
        nodes=args.nodes,
        calls=args.call or (),
        settle=args.settle,
        **passed_on(
            args,
            "scenario srdf moveit_config timeout autonomy seed meshcat realtime record latency python2 "
            "settle_after bag",
        ),
    )
    return show_report(report, args.json, print_line)


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Registers ``flexbe-run`` on the CLI's subparsers."""
    p = sub.add_parser(
        "flexbe-run",
        help="run a FlexBE behaviour (lecture 7) of catkin workspaces headless, in simulated time",
        description="Builds BEHAVIOR (its manifest name, as be_launcher -b takes it, or its *_sm.py) "
        "from the workspaces' packages and ticks its state machine at FlexBE's rate on the scenario's "
        "cell until it returns an outcome.",
    )
    p.add_argument("behavior", metavar="BEHAVIOR")
    p.add_argument(
        "--workspace",
        action="append",
        required=True,
        metavar="DIR",
        help="a catkin src folder (repeatable); a --launch, --world or --robot finds its packages there too",
    )
    add_cell_options(p, workspace=False)
    p.set_defaults(nodes=[])  # a launch's Python nodes (set with --launch), run in the session
    add_shared_options(p, "--srdf --moveit-config --call --settle")
    p.add_argument(
        "--timeout", type=float, default=600.0, metavar="S", help="simulated seconds (default 600)"
    )
    p.add_argument("--autonomy", choices=list(AUTONOMY_LEVELS), default="full", help="default full")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE", help="a behaviour parameter")
    add_shared_options(p, "--seed --json --record --meshcat --realtime --latency --settle-after --bag")
    p.add_argument(
        "--python2",
        action="store_true",
        help="convert the workspaces' modules from Python 2 (2to3, tabs as Python 2 reads them) as they load",
    )
    p.add_argument("-q", "--quiet", action="store_true", help="no log lines while it runs")
    p.set_defaults(func=cmd_flexbe_run)
