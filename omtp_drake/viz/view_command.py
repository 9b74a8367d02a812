"""``omtp-drake view FILE.urdf[.xacro]|FILE.sdf|FILE.world``: the model (or a Gazebo world's
models, each where the world puts it) in Meshcat with joint sliders.

Registered on the main command line by :func:`add_view_command`. ``--json`` lists what
was parsed (:func:`omtp_drake.viz.model_view.model_info`) instead of showing it;
``--screenshot PNG`` writes a picture of the view and ``--images DIR`` the sensors'
images and point clouds, and exit; otherwise the view runs
until Meshcat's Stop button, ``--timeout`` or Ctrl-C.
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
from collections.abc import Callable
from typing import Any

from omtp_drake.errors import ConfigError


def view_model_config(args: argparse.Namespace) -> Any:
    """The model ``view`` shows: the description file's (its packages found in
    ``--workspace`` folders, ``ROS_PACKAGE_PATH`` and next to the file), or the robot
    description a ``--launch`` loads on ``--param`` (rviz's ``robot_description``)."""
    from omtp_drake.scenario import model_from_file
    from omtp_drake.scenario.models import file_workspace
    from omtp_drake.scenario.robot_world import RobotSpawn, parse_robot

    given = [RobotSpawn(f) for f in (args.file, args.world) if f] + [parse_robot(r) for r in args.robot]
    if len(given) + (args.launch is not None) != 1:
        raise ConfigError(
            "view shows one model: give FILE.urdf[.xacro]|FILE.sdf|FILE.world (or --robot FILE, --world "
            "FILE.world) or --launch 'PKG FILE.launch [ARG:=VALUE ...]'"
        )
    args_map = dict(_pair(a, "--arg") for a in args.arg)
    if args.launch is not None:
        if args_map:  # roslaunch's words: the launch's own args
            args.launch += "".join(f" {shlex.quote(f'{name}:={value}')}" for name, value in args_map.items())
        return args.launch_description(args.launch, args.workspace, args.param)
    spawn = given[0]
    if str(spawn.file).endswith(".world") and args.world_description is not None:
        models, warnings = args.world_description(spawn.file, args.workspace)
        for line in warnings:
            sys.stderr.write(f"omtp-drake: warning: {line}\n")
        return models
    return model_from_file(
        spawn.file,
        file_workspace(spawn.file, args.workspace),
        name=spawn.name,
        xyz=spawn.xyz,
        rpy=spawn.rpy,
        static=True,
        args=args_map,
    )


def _pair(text: str, flag: str) -> tuple[str, str]:
    name, sep, value = text.partition(":=") if ":=" in text else text.partition("=")
    if not sep or not name:
        raise ConfigError(f"{flag} {text!r}: give NAME:=VALUE (or NAME=VALUE)")
    return name, value


def cmd_view(args: argparse.Namespace) -> int:
    """``view``: exit 0 when the model was shown (or listed)."""
    model = view_model_config(args)
    if args.json is not None:
        from omtp_drake.viz.model_view import model_info

        info = (
            {"world": args.file, "models": [model_info(m) for m in model]}
            if isinstance(model, list)
            else model_info(model)
        )
        text = json.dumps(info, indent=2)
        if args.json == "-":
            sys.stdout.write(text + "\n")
        else:
            with open(args.json, "w") as f:
                f.write(text + "\n")
        return 0
    from omtp_drake.viz.meshcat import start_meshcat
    from omtp_drake.viz.model_view import build_model_view, run_view, save_sensor_images, screenshot_view

    positions = {}
    for text in args.position:
        name, value = _pair(text, "--position")
        try:
            positions[name] = float(value)
        except ValueError:
            raise ConfigError(f"--position {text!r}: {value!r} is not a number") from None
    view = build_model_view(model, start_meshcat(), positions)
    if args.images:
        for path in save_sensor_images(view, args.images):
            sys.stdout.write(f"{path}\n")
    if args.screenshot:
        sys.stdout.write(f"screenshot: {screenshot_view(view, args.screenshot)}\n")
    if args.screenshot or args.images:
        return 0
    sys.stdout.write(f"Meshcat: {view.meshcat.web_url()} (a slider per joint; Stop or Ctrl-C to end)\n")
    sys.stdout.flush()
    run_view(view, args.timeout)
    return 0


def add_view_command(
    sub: argparse._SubParsersAction,
    launch_description: Callable[..., Any],
    world_description: Callable[..., Any] | None = None,
) -> None:
    """Registers ``omtp-drake view``; ``launch_description(spec, workspace, param)`` gives the
    model a ``--launch`` loads (:func:`omtp_drake.launch.description.launch_description`,
    a layer above this one), ``world_description(file, workspace)`` the models of a
    ``FILE.world`` and the lines to warn with (:func:`~omtp_drake.launch.description.world_description`)."""
    p = sub.add_parser(
        "view",
        help="show a URDF/xacro/SDF model in Meshcat, a slider per joint (rviz + joint_state_publisher_gui)",
        description="Shows the model of FILE in Meshcat with a slider per movable joint, its camera "
        "sensors' images and a depth camera's point cloud.",
    )
    p.add_argument("file", metavar="FILE.urdf[.xacro]|FILE.sdf|FILE.world", nargs="?")
    p.add_argument("--world", metavar="FILE.world", help="a Gazebo world file, instead of FILE")
    p.add_argument(
        "--robot",
        action="append",
        default=[],
        metavar="[NAME=]FILE[@X,Y,Z[,R,P,Y]]",
        help="the model of a URDF, xacro or SDF file, instead of FILE, placed as spawn_model places it",
    )
    p.add_argument(
        "--launch",
        metavar="'PKG FILE.launch [ARG:=VALUE ...]'",
        help="the robot description a launch file loads (as roslaunch takes it), instead of FILE",
    )
    p.add_argument(
        "--param",
        default="/robot_description",
        metavar="NAME",
        help="with --launch: the parameter holding the description (default /robot_description, as rviz)",
    )
    p.add_argument(
        "--workspace",
        action="append",
        default=[],
        metavar="DIR",
        help="a folder of ROS packages the file names ($(find PKG), package://); repeatable",
    )
    p.add_argument(
        "--arg",
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="an argument of the file's xacro, or of the --launch file (repeatable)",
    )
    _add_output_options(p)
    p.set_defaults(func=cmd_view, launch_description=launch_description, world_description=world_description)


def _add_output_options(p: argparse.ArgumentParser) -> None:
    """What ``view`` writes instead of serving (a listing, a picture, images), its start pose
    and its timeout."""
    p.add_argument(
        "--json", nargs="?", const="-", metavar="FILE", help="list links, joints, frames, sensors, plugins"
    )
    p.add_argument("--screenshot", metavar="PNG", help="write a PNG of the view and exit")
    p.add_argument(
        "--images",
        metavar="DIR",
        help="write each camera sensor's colour and depth images (PNG) and point cloud (PLY) there, and exit",
    )
    p.add_argument(
        "--position", action="append", default=[], metavar="JOINT=VALUE", help="a joint's start position"
    )
    p.add_argument("--timeout", type=float, default=math.inf, metavar="S", help="end after S wall seconds")
