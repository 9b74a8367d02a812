"""The ``omtp-drake`` command line.

Every command that builds a cell takes the same cell options (SCENARIO or ``--scenario
NAME|FILE``, ``--launch``, ``--world``, ``--robot``, ``--workspace``, ``--arg``), resolved
by one function into a typed scenario (:mod:`omtp_drake.launch.options`); options go
anywhere on a command's line. Errors are printed as one line on stderr with exit code 2;
no traceback.
"""

from __future__ import annotations

import argparse
import gc
import json
import logging
import math
import re
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING

from omtp_drake.errors import ConfigError, OmtpError

if TYPE_CHECKING:
    from pydrake.systems.framework import Context

    from omtp_drake.cell.station import Station
    from omtp_drake.scenario import Scenario

_log = logging.getLogger("omtp_drake")


def _parse_poses(items: Sequence[str]) -> dict[str, str]:
    poses = {}
    for item in items:
        robot, sep, pose = item.partition("=")
        if not sep or not robot or not pose:
            raise ConfigError(f"--pose takes ROBOT=POSE (e.g. robot1=R1Home), got {item!r}")
        poses[robot] = pose
    return poses


def cmd_scenarios(args: argparse.Namespace) -> int:
    from omtp_drake.scenario import load_scenario, scenario_names

    for name in scenario_names():
        print(f"{name:28s} {load_scenario(name).description}")
    return 0


def _run_and_report(args: argparse.Namespace, scenario: Scenario | str, *, progress: bool) -> int:
    """Runs ``scenario``'s task with the view options of ``args``; prints the result."""
    from omtp_drake.tasks.run import TaskRun, run_task

    runs: list[TaskRun] = []

    def started(run: TaskRun) -> None:
        runs.append(run)  # keeps the Meshcat server alive until we are done
        meshcat = run.runtime.station.meshcat
        if meshcat is not None:
            print(f"Meshcat: {meshcat.web_url()}", flush=True)
        if args.realtime:
            run.runtime.simulator.set_target_realtime_rate(1.0)

    result = run_task(
        scenario,
        seed=args.seed,
        duration=getattr(args, "duration", None),
        parts=args.parts,
        meshcat=args.meshcat or args.serve,
        record=args.record,
        progress=progress,
        on_start=started,
    )
    print(result.format())
    if getattr(args, "json", None):
        with open(args.json, "w") as f:
            json.dump(result.to_dict(), f, indent=2)
        print(f"result: {args.json}")
    if args.record:
        print(f"replay: {args.record} (open it in any browser)")
    if args.serve:
        _serve(runs[0].runtime.station.meshcat)
    return 0 if result.success else 1


def _serve(meshcat) -> None:
    """Keeps Meshcat serving until Ctrl-C, if a terminal is there to press it."""
    import time

    if not sys.stdin.isatty():
        print("--serve: no terminal attached (nobody could press Ctrl-C); not serving on")
        return
    print(f"Meshcat is serving at {meshcat.web_url()}; press Ctrl-C to quit.", flush=True)
    try:
        while True:
            time.sleep(0.5)
    except KeyboardInterrupt:
        print()


def cmd_run(args: argparse.Namespace) -> int:
    from omtp_drake.batch.command import show_progress

    return _run_and_report(args, args.scenario, progress=show_progress(args))


def cmd_demo(args: argparse.Namespace) -> int:
    """The main demo: the fill-a-bin challenge."""
    from omtp_drake.batch.command import show_progress

    return _run_and_report(args, "fill_bin", progress=show_progress(args))


def cmd_screenshot(args: argparse.Namespace) -> int:
    """A PNG of a recorded replay at a replay time, rendered by headless chromium."""
    from omtp_drake.viz.browser import screenshot

    width, sep, height = args.size.partition("x")
    if not (sep and width.isdigit() and height.isdigit()):
        raise ConfigError(f"--size takes WIDTHxHEIGHT (e.g. 1280x800), got {args.size!r}")
    png = screenshot(
        args.replay,
        args.output,
        time=args.time,
        size=(int(width), int(height)),
        hide=args.hide,
        timeout_s=args.timeout,
    )
    print(f"screenshot: {png}")
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    from omtp_drake.bench_command import measure

    report = measure(
        args.repeats,
        args.bare_seconds,
        progress=lambda text: print(f"measuring {text} ...", file=sys.stderr, flush=True),
    )
    print(report.table())
    return 0


def _simulated_station(
    scenario: Scenario, time: float, poses: dict[str, str] | None = None, camera: str | None = None
) -> tuple[Station, Context]:
    """(station, root context) of :func:`~omtp_drake.sim.runtime.runtime_at` at ``--time``."""
    from omtp_drake.sim.runtime import runtime_at

    if not (math.isfinite(time) and time >= 0):
        raise ConfigError(f"--time {time!r} is invalid; valid: a finite time >= 0 s")
    runtime = runtime_at(scenario, time, poses, camera)
    return runtime.station, runtime.context


def cmd_tf_echo(args: argparse.Namespace) -> int:
    from omtp_drake.sim.tf import TfBuffer, format_transform, transform_json

    station, context = _simulated_station(args.scenario, args.time, _parse_poses(args.pose))
    stamped = TfBuffer.from_context(station, context).lookup_transform(args.source, args.target)
    text = transform_json if args.json else format_transform
    print(text(stamped.transform, stamped.time))
    return 0


def cmd_camera(args: argparse.Namespace) -> int:
    if args.image:
        scenario = args.scenario
        config = next((c for c in scenario.cameras if c.name == args.camera), None)
        if config is not None and not config.rgbd:
            raise ConfigError(
                f"camera {args.camera!r} of {scenario.name} has no RGB-D view for --image; enable it in a "
                f"scenario with base: {scenario.name} and cameras: [{{name: {args.camera}, rgbd: true}}]"
            )
    from omtp_drake.gazebo.logical_camera import camera_view

    station, context = _simulated_station(args.scenario, args.time, camera=args.camera)
    if not station.scenario.plugin_names.camera_listing(args.camera).advertised:
        raise ConfigError(
            f"logical camera {args.camera!r} publishes nothing: its plugin stopped loading "
            "(a <known_model_types> without <type>); valid: a camera whose plugin loads"
        )
    # What the camera's topic (/omtp/<camera>) carries, by its plugin's rules, as rostopic echo shows.
    image = camera_view(station, args.camera).image(context)
    print(json.dumps(image.to_dict()) if args.json else str(image))
    if args.image:
        from omtp_drake.cell.rgbd import color_image, save_png

        color = color_image(station.diagram, context, args.camera)
        path = save_png(color, args.image)
        if not args.json:
            print(f"colour image: {path} ({color.width()} x {color.height()})")
    return 0


def cmd_frames(args: argparse.Namespace) -> int:
    from omtp_drake.sim.tf import TfBuffer
    from omtp_drake.viz.tree import view_frames

    station, context = _simulated_station(args.scenario, args.time)
    paths = view_frames(
        TfBuffer.from_context(station, context), args.output, title=f"Frame tree of {station.scenario.name}"
    )
    for path in paths:
        print(path)
    return 0


def _warn(line: str) -> None:
    print(f"omtp-drake: warning: {line}", file=sys.stderr)


def _add_view_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--meshcat",
        action="store_true",
        help="show the run in a live Meshcat view (its URL is printed first)",
    )
    p.add_argument("--realtime", action="store_true", help="pace the simulation at real time")
    p.add_argument(
        "--serve",
        action="store_true",
        help="keep the Meshcat view serving after the run, until Ctrl-C (needs a terminal)",
    )
    p.add_argument("--record", metavar="HTML", help="write a standalone Meshcat replay")


def _add_task_commands(sub: argparse._SubParsersAction) -> None:
    """Registers the commands that list scenarios and run their tasks: scenarios, demo, run."""
    from omtp_drake.batch.command import add_progress_options
    from omtp_drake.launch.options import add_cell_options

    p = sub.add_parser("scenarios", help="list the scenario names")
    p.set_defaults(func=cmd_scenarios)

    p = sub.add_parser("demo", help="the main demo: robot 2 fills bin 1 (fill_bin)")
    p.add_argument("--parts", type=int, default=None, help="parts to place (default 10)")
    p.add_argument("--seed", type=int, default=None, help="override the scenario's seed")
    _add_view_options(p)
    add_progress_options(p)
    p.set_defaults(func=cmd_demo)

    p = sub.add_parser("run", help="run a scenario's pick-and-place task")
    add_cell_options(p, positional=True)
    p.add_argument("--seed", type=int, default=None, help="override the scenario's seed")
    p.add_argument(
        "--duration", type=float, default=None, help="simulated seconds at most (default 30 per part)"
    )
    p.add_argument("--parts", type=int, default=None, help="parts to place")
    _add_view_options(p)
    p.add_argument("--json", metavar="FILE", help="write the result as JSON")
    add_progress_options(p)
    p.set_defaults(func=cmd_run)


def _add_replay_commands(sub: argparse._SubParsersAction) -> None:
    """Registers the commands on recorded replays: screenshot."""
    p = sub.add_parser("screenshot", help="a PNG of a recorded replay (headless chromium)")
    p.add_argument("replay", metavar="HTML", help="a replay written with --record")
    p.add_argument(
        "-o",
        "--output",
        default="replay.png",
        metavar="PNG",
        help="where to write the PNG (default: replay.png)",
    )
    p.add_argument(
        "--time",
        type=float,
        default=None,
        metavar="T",
        help="replay time to show, in simulated seconds (default: the end)",
    )
    p.add_argument("--size", default="1280x800", metavar="WxH", help="default 1280x800")
    p.add_argument(
        "--hide",
        action="append",
        default=[],
        metavar="PATH",
        help="Meshcat path to switch off, e.g. /frusta or /detections (repeatable)",
    )
    p.add_argument(
        "--timeout", type=float, default=120.0, metavar="S", help="give up after S seconds (default 120)"
    )
    p.set_defaults(func=cmd_screenshot)


def _add_simulate_first_option(p: argparse.ArgumentParser, note: str = "") -> None:
    """``--time T``: the commands that look at the cell simulate it, arms holding
    their initial pose, to T s first."""
    p.add_argument(
        "--time",
        type=float,
        default=0.5,
        metavar="T",
        help="simulate (arms holding their initial pose) to T s first (default 0.5)"
        + (f"; {note}" if note else ""),
    )


def _add_tf_echo_command(sub: argparse._SubParsersAction) -> None:
    """Registers ``omtp-drake tf-echo``: a frame's pose in another, like ROS tf_echo."""
    from omtp_drake.launch.options import add_cell_options

    p = sub.add_parser("tf-echo", help="pose of TARGET in SOURCE, like ROS tf_echo")
    add_cell_options(p, positional=True)
    p.add_argument("source", metavar="SOURCE")
    p.add_argument("target", metavar="TARGET")
    p.add_argument(
        "--pose",
        action="append",
        default=[],
        metavar="ROBOT=POSE",
        help="arm at a named pose (default Home), e.g. robot1=R1Up",
    )
    _add_simulate_first_option(p, "the cameras have images then; detected-model frames are looked up too")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_tf_echo)


def _add_inspect_commands(sub: argparse._SubParsersAction) -> None:
    """Registers the commands that inspect the cell at a time, like ROS tools: tf-echo, camera, frames."""
    from omtp_drake.launch.options import add_cell_options

    _add_tf_echo_command(sub)
    p = sub.add_parser("camera", help="what a logical camera sees, like rostopic echo")
    add_cell_options(p, positional=True)
    p.add_argument("--camera", required=True, metavar="NAME", help="e.g. logical_camera_1")
    _add_simulate_first_option(p)
    p.add_argument(
        "--json", action="store_true", help="print JSON (keys time, camera_name, camera_pose, models)"
    )
    p.add_argument(
        "--image",
        metavar="PNG",
        help="also save the camera's colour image (its RGB-D view: `rgbd: true` in the scenario)",
    )
    p.set_defaults(func=cmd_camera)

    p = sub.add_parser("frames", help="draw the frame tree (PDF and PNG), like ROS view_frames")
    add_cell_options(p, positional=True)
    p.add_argument(
        "-o",
        "--output",
        default="frames",
        metavar="FILE",
        help="output stem; FILE.pdf and FILE.png are written (default: frames)",
    )
    _add_simulate_first_option(p)
    p.set_defaults(func=cmd_frames)


def _add_bench_command(sub: argparse._SubParsersAction) -> None:
    """Registers ``omtp-drake bench``: how fast the cell runs."""
    p = sub.add_parser(
        "bench",
        help="how fast the cell runs: full runs against the bare plant, build time, pick cycles",
        description="Runs fill_bin, lecture7_conveyor_pick and lecture7_conveyor (10 parts on the "
        "belt) as users run them and as a bare plant, and fill_bin's job in PyBullet and MuJoCo (with the "
        "bench extra), and prints the speed table (a few minutes).",
    )
    p.add_argument(
        "--repeats", type=int, default=2, help="interleaved rounds of all cases; medians count (default 2)"
    )
    p.add_argument(
        "--bare-seconds", type=float, default=10.0, help="simulated seconds of a bare-plant run (default 10)"
    )
    p.set_defaults(func=cmd_bench)


def _values_that_look_like_options(argv: Sequence[str]) -> list[str]:
    """``--seeds -1:3`` as ``--seeds=-1:3``: a value that starts with a minus sign and
    a digit is the option's value (argparse would take it for an option and print its
    usage), so the option's own check can say what is wrong with it."""
    out: list[str] = []
    for i, token in enumerate(argv):
        if token == "--" or token.endswith(".py"):  # a script's own arguments stay as they are
            return out + list(argv[i:])
        previous = out[-1] if out else ""
        if re.match(r"-[0-9.]", token) and previous.startswith("--") and "=" not in previous:
            out[-1] = f"{previous}={token}"
        else:
            out.append(token)
    return out


def build_parser() -> argparse.ArgumentParser:
    """The ``omtp-drake`` parser. Its commands' modules are imported here, not when this
    module is: a Dask worker process (``grade``, ``batch``) imports this module again as its
    ``__main__`` (multiprocessing's spawn) and never parses a command line, so it skips them
    (about 1 CPU s of pydrake and the launch reader per worker)."""
    from omtp_drake.batch.command import add_batch_command
    from omtp_drake.grading.cli import add_commands as add_ros_commands
    from omtp_drake.launch.description import launch_description, world_description
    from omtp_drake.launch.options import CommandParser
    from omtp_drake.ros.flexbe.cli import add_commands as add_flexbe_commands
    from omtp_drake.ros2.run import add_commands as add_ros2_commands
    from omtp_drake.viz.view_command import add_view_command

    parser = CommandParser(prog="omtp-drake", description="The OMTP factory cell simulated with Drake.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_task_commands(sub)
    _add_replay_commands(sub)
    _add_inspect_commands(sub)
    _add_bench_command(sub)
    add_batch_command(sub)
    add_ros_commands(sub)
    add_flexbe_commands(sub)
    add_ros2_commands(sub)
    add_view_command(sub, launch_description, world_description)
    return parser


def _quiet_drake(verbose: bool) -> None:
    """Drake warns on every build that the floor plane takes no deformable contact: its log
    shows errors only, unless ``--verbose``. (pydrake sets its logger's level when first
    imported, so it is imported first.)"""
    import numpy as np
    import pydrake.common  # noqa: F401

    logging.getLogger("drake").setLevel(logging.INFO if verbose else logging.ERROR)
    np.set_printoptions(precision=4, suppress=True)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(_values_that_look_like_options(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING, format="%(levelname)s %(name)s: %(message)s"
    )
    from omtp_drake.launch.options import resolve_cell_options

    try:
        if getattr(args, "prerequisite", None) is not None:
            args.prerequisite()  # what the command needs installed (an extra), said before Drake loads
        _quiet_drake(args.verbose)
        resolve_cell_options(args, warn=_warn)
        if argv is None:  # the process's own command line: its modules and scenario live as long as it,
            gc.freeze()  # and the collections of the run skip them
        return args.func(args)
    except OmtpError as e:
        print(f"omtp-drake: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
