"""What ``/tf`` costs ``omtp-drake ros2`` per simulated second (issue 44).

Steps ``lecture6_assignment1`` as ``omtp-drake ros2`` does (10 ms) for SECONDS simulated
seconds and, at the joint state rate (50 Hz), runs the parts of ``/tf`` one at a time,
timing only them (CPU time of this process, ``time.process_time``; wall time too):

- ``edges``: :class:`~omtp_drake.sim.tf_broadcast.TfBroadcast`: the moving edges and the
  logical cameras' detected frames, from the plant's Context and the tf buffer;
- ``<route> unheard``: ``/tf`` by a route of :mod:`omtp_drake.ros2.packed_topics` (``rclpy``
  with the built ``tf2_msgs``, ``cyclone``), nobody reading: nothing is built (the node's rule);
- ``<route>+bag``: the same edges as a ``tf2_msgs/TFMessage``, written by that route on
  loopback in a private domain and into an MCAP bag (``--bag``: always wanted).

Printed: milliseconds per simulated second of each, and the messages' sizes. Numbers
only, no pass/fail; the machine is shared: the load average is printed.

    python bench/bench_tf.py [--seconds 5]
"""

import argparse
import logging
import os
import tempfile
import time
from pathlib import Path

logging.getLogger("drake").setLevel(logging.ERROR)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    args = parser.parse_args()

    import rclpy

    from omtp_drake.ros.bag.writer import Ros2Bag
    from omtp_drake.ros2.bag import record_publishers
    from omtp_drake.ros2.dds_types import CycloneParticipant
    from omtp_drake.ros2.network import Ros2Network
    from omtp_drake.ros2.packed_topics import PackedTopics
    from omtp_drake.ros2.tf_publisher import TfTopics
    from omtp_drake.script import Cell
    from omtp_drake.sim.tf_broadcast import TfBroadcast

    network = Ros2Network(1 + os.getpid() % 101)
    network.apply()
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=network.domain_id)
    with Cell("lecture6_assignment1") as cell, tempfile.TemporaryDirectory() as folder:
        broadcast = TfBroadcast(cell.station.plant, cell.tf)
        dds = CycloneParticipant(network)
        bags = {route: Ros2Bag(Path(folder) / f"{route}.mcap") for route in ("rclpy", "cyclone")}
        jobs = {"edges": lambda t: broadcast.moving(cell.runtime.context) + broadcast.detected()}
        for route, bag in bags.items():
            plain, recorded = (rclpy.create_node(f"bench_tf_{route}{i}", context=context) for i in (1, 2))
            record_publishers(recorded, bag, lambda: cell.time)
            for name, node, with_bag in ((f"{route} unheard", plain, None), (f"{route}+bag", recorded, bag)):
                topics = PackedTopics(node, lambda: dds, with_bag)
                topics.route = route  # as chosen where the types cannot be built, for "cyclone"
                jobs[name] = TfTopics(cell, topics)
        cpu = dict.fromkeys(jobs, 0.0)
        wall = dict.fromkeys(jobs, 0.0)
        calls = 0
        next_due = 0.0
        while cell.time < args.seconds - 1e-9:
            cell.runtime.advance_to(cell.time + 0.01)
            if cell.time + 1e-9 < next_due:
                continue
            next_due += 0.02
            calls += 1
            for name, job in jobs.items():
                c0, w0 = time.process_time(), time.perf_counter()
                job(cell.time)
                cpu[name] += time.process_time() - c0
                wall[name] += time.perf_counter() - w0
        for bag in bags.values():
            bag.close()
        edges = broadcast.moving(cell.runtime.context) + broadcast.detected()
        size = (Path(folder) / "cyclone.mcap").stat().st_size
    context.try_shutdown()
    print(
        f"lecture6_assignment1, {args.seconds:g} simulated s, {calls} /tf messages of {len(edges)} transforms"
    )
    print(f"load average: {os.getloadavg()[0]:.2f}")
    print(f"{'part':<14}{'CPU ms/sim s':>14}{'wall ms/sim s':>15}")
    for name in jobs:
        print(f"{name:<14}{1e3 * cpu[name] / args.seconds:>14.1f}{1e3 * wall[name] / args.seconds:>15.1f}")
    print(f"bag: {size / 1e3 / args.seconds:.1f} kB per simulated s (/tf and /tf_static, zstd)")


if __name__ == "__main__":
    main()
