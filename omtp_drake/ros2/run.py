"""``omtp-drake ros2``: a scenario's cell as a ROS 2 node until its time is up or
Ctrl-C (registered with :func:`add_commands`).

Without ``--realtime`` the cell runs as fast as it can, ``/clock`` leading every
message (peers with ``use_sim_time`` follow it); with it, the simulator is paced
to the wall clock for a person watching in rviz2. ``--timeout S`` ends the run
after S simulated seconds, as ``ros-run``'s does. Ctrl-C (SIGINT) and SIGTERM end
it between two steps: the node leaves the graph and the process exits with 0.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from omtp_drake.errors import check_duration
from omtp_drake.launch.options import add_cell_options
from omtp_drake.ros.run.command import add_shared_options, print_line
from omtp_drake.ros2.launched_nodes import launched_nodes
from omtp_drake.ros2.network import Ros2Network, choose_network, import_rclpy

if TYPE_CHECKING:
    from omtp_drake.launch.ros2_nodes import Ros2NodeProgram
    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.scenario import Scenario
    from omtp_drake.script import Cell


@dataclass(frozen=True)
class Ros2RunOptions:
    """How ``omtp-drake ros2`` runs a cell.

    Attributes:
        scenario: the scenario's name or YAML path, or a robot's URDF, xacro or SDF file
            (spawned into Gazebo's empty world, as ``ros-run --robot`` does), or a
            resolved :class:`~omtp_drake.scenario.Scenario` (the CLI's cell options: a launch
            file's, a world's): the node serves the Gazebo plugins of whatever it holds.
        seed: overrides the scenario's seed.
        timeout: simulated seconds to run (None: until stopped).
        realtime: pace to the wall clock.
        meshcat: serve a Meshcat view too.
        urdf: also write the URDF the node publishes to this file (for a peer's
            robot_state_publisher, which reads it as a parameter).
        bag: record every topic into this ROS 2 bag (``.mcap``).
        nodes: the launch's own ROS 2 nodes (a program and its arguments each), run beside
            the cell while it runs (:mod:`~omtp_drake.ros2.launched_nodes`).
    """

    scenario: Scenario | str
    seed: Optional[int] = None
    timeout: Optional[float] = None
    realtime: bool = False
    meshcat: bool = False
    urdf: Optional[str] = None
    bag: Optional[str] = None
    nodes: Sequence[tuple[Ros2NodeProgram, Sequence[str]]] = ()

    def __post_init__(self) -> None:
        if self.timeout is not None:
            check_duration("--timeout", self.timeout)

    def cell(self) -> Cell:
        """The cell to run (the one place a new option of ``Cell``, e.g. a robot of
        the user's own, is passed on)."""
        from omtp_drake.scenario import as_scenario
        from omtp_drake.script import Cell

        scenario = as_scenario(self.scenario)
        if self.seed is not None:
            scenario = replace(scenario, seed=self.seed)
        # Parts come when a peer calls the spawner's services, as under ros-run.
        return Cell(scenario, realtime=self.realtime, meshcat=self.meshcat, auto_spawn=False)


@contextlib.contextmanager
def _stop_on_signals() -> Iterator[threading.Event]:
    """An event set by SIGINT or SIGTERM while the block runs (their handlers restored after)."""
    stop = threading.Event()

    def handler(signum: int, frame: object) -> None:
        stop.set()

    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


@contextlib.contextmanager
def _bag(path: Optional[str]) -> Iterator[Optional[Ros2Bag]]:
    """The run's bag (``--bag``), finished when the run ends however it ends; None without one."""
    if path is None:
        yield None
        return
    from omtp_drake.ros.bag.writer import Ros2Bag

    with Ros2Bag(path) as bag:
        yield bag


def run_ros2(options: Ros2RunOptions, network: Ros2Network, say: Callable[[str], None]) -> float:
    """Runs the cell of ``options`` as a ROS 2 node on ``network`` until its timeout
    or a signal; ``say`` gets the lines to show. Returns the simulated time reached."""
    import_rclpy()  # before anything imports a message package: a missing extra is said at once
    from omtp_drake.ros2.bridge import NODE_NAME, Ros2Cell

    with _stop_on_signals() as stop:
        with options.cell() as cell:
            with _bag(options.bag) as bag, Ros2Cell(cell, network, bag) as node:
                say(
                    f"omtp-drake ros2: {cell.scenario.name} as node /{NODE_NAME} on {network.describe()}; "
                    f"join it with: export {' '.join(f'{k}={v}' for k, v in network.environment().items())}"
                )
                if bag is not None:
                    say(f"recording every topic into the ROS 2 bag {bag.path}")
                if options.urdf:
                    Path(options.urdf).write_text(node.description)
                    say(f"URDF written to {options.urdf}")
                if cell.url:
                    say(f"Meshcat: {cell.url}")
                # Realtime pacing counts from here, not from when the cell was built.
                cell.runtime.simulator.ResetStatistics()
                end = options.timeout
                with launched_nodes(options.nodes, {**os.environ, **network.environment()}, say):
                    while not stop.is_set() and (end is None or cell.time < end - 1e-9):
                        node.step(min(0.01, end - cell.time) if end is not None else 0.01)
                    say(f"omtp-drake ros2: stopped at t={cell.time:.2f} s (simulated)")
                return cell.time


def cmd_ros2(args: argparse.Namespace) -> int:
    options = Ros2RunOptions(
        args.scenario,
        seed=args.seed,
        timeout=args.timeout,
        realtime=args.realtime,
        meshcat=args.meshcat,
        urdf=args.urdf,
        bag=args.bag,
        nodes=[(node.program, node.argv) for node in args.ros2_nodes if node.program is not None],
    )
    run_ros2(options, choose_network(args.domain_id, subnet=args.network), print_line)
    return 0


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Registers ``omtp-drake ros2``."""
    p = sub.add_parser(
        "ros2",
        help="run a scenario's cell as ROS 2 nodes over DDS (the ros2 extra): /clock, /joint_states, "
        "/robot_description, cameras, /set_joint_trajectory, gripper and belt services",
    )
    add_cell_options(p, positional=True)
    p.add_argument("--seed", type=int, default=None, help="override the scenario's seed")
    p.add_argument("--timeout", type=float, default=None, metavar="S", help="end after S simulated seconds")
    p.add_argument("--realtime", action="store_true", help="pace the simulation to the wall clock")
    p.add_argument("--meshcat", action="store_true", help="also serve a live Meshcat view")
    p.add_argument(
        "--urdf",
        default=None,
        metavar="FILE",
        help="write the published URDF there (for robot_state_publisher)",
    )
    add_shared_options(p, "--bag")
    p.add_argument(
        "--domain-id",
        type=int,
        default=None,
        metavar="N",
        help="ROS_DOMAIN_ID (0-232; default: $ROS_DOMAIN_ID, else one chosen and printed)",
    )
    p.add_argument(
        "--network",
        action="store_true",
        help="let DDS discovery reach other machines of the local network (default: this machine only)",
    )
    # (rclpy first: without the extra, the command says so before it loads Drake and the cell)
    p.set_defaults(func=cmd_ros2, ros2_nodes=[], prerequisite=import_rclpy)

    about = (
        "print the folder of the ROS 2 interface packages no wheel ships (gazebo_msgs, control_msgs, "
        "tf2_msgs), building them first with the system's compiler if the cache lacks them: "
        "export PYTHONPATH=$(omtp-drake ros2-interfaces) lets a node of yours import them"
    )
    p = sub.add_parser("ros2-interfaces", help=about, description=about)
    p.set_defaults(func=cmd_ros2_interfaces)


def cmd_ros2_interfaces(args: argparse.Namespace) -> int:
    """``omtp-drake ros2-interfaces``: the built packages' folder on stdout (an error line
    without a compiler, exit code 2)."""
    from omtp_drake.ros2.interface_build import interfaces_path

    print_line(str(interfaces_path()))
    return 0
