"""What ``omtp-drake ros2`` costs and delivers: the cell's topics in a subscriber of
another process, over Fast DDS on loopback.

Three runs of SECONDS simulated seconds of a case, stepped as ``omtp-drake ros2`` steps
(10 ms). ``--case assignment1`` (the default): ``lecture6_assignment1`` with camera 1's
RGB-D view (320 x 213, 10 Hz); ``--case tutorial``: the URDF tutorial's robot
(tests/fixtures/tutorial_ws: its joint state publisher at 20 Hz and its 640 x 480, 20 Hz
depth camera) in Gazebo's empty world, as ``omtp-drake ros2 ROBOT`` serves it:

1. ``bare``: the cell alone, no ROS 2;
2. ``ros2``: the cell as a ROS 2 node, nobody listening (the RGB-D view is not rendered);
3. ``ros2+sub``: the same with a subscriber process on the case's TOPICS: /clock,
   /joint_states, the camera's image_raw, depth/image_raw and points (and the logical
   camera's poses).

Printed: wall and CPU milliseconds per simulated second of each (the best of the
repeats; CPU time of the cell's process, all its threads: less swayed by other load),
the cost of ROS 2 per simulated second (2 - 1: publishing; 3 - 1: publishing with a
subscriber, rendering the RGB-D view included), and for every run 3, per topic: messages
sent and received, messages per wall second, size, and latency from ``publish`` in
the cell to the subscriber's callback (median, 95th percentile, max; both processes
read the same clock). ``--realtime`` paces run 3 to the wall clock (the rates are
then the nominal ones: 100, 50, 10 Hz); without it, a subscriber slower than the cell
loses messages (reliable KEEP_LAST queues drop their oldest) and the table says which.
No pass/fail; numbers only. The machine is shared: the runs are interleaved when
``--repeats`` > 1, and the load average is printed.

    python bench/bench_ros2.py [--case assignment1|tutorial] [--seconds 10] [--repeats 2] [--realtime]
"""

import argparse
import json
import logging
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

logging.getLogger("drake").setLevel(logging.ERROR)

SCENARIO = "base: lecture6_assignment1\ncameras: [{name: logical_camera_1, rgbd: true}]\n"
ROBOT = Path(__file__).resolve().parent.parent / "tests/fixtures/tutorial_ws/src/slider_arm_description/urdf"
ROBOT = ROBOT / "slider_arm.urdf.xacro"
CASES = {
    "assignment1": {
        "/clock": "rosgraph_msgs.msg:Clock",
        "/joint_states": "sensor_msgs.msg:JointState",
        "/omtp/logical_camera_1/poses": "geometry_msgs.msg:PoseArray",
        "/logical_camera_1/image_raw": "sensor_msgs.msg:Image",
        "/logical_camera_1/depth/image_raw": "sensor_msgs.msg:Image",
        "/logical_camera_1/points": "sensor_msgs.msg:PointCloud2",
    },
    "tutorial": {
        "/clock": "rosgraph_msgs.msg:Clock",
        "/joint_states": "sensor_msgs.msg:JointState",
        "/tip_camera/image_raw": "sensor_msgs.msg:Image",
        "/tip_camera/depth/image_raw": "sensor_msgs.msg:Image",
        "/tip_camera/points": "sensor_msgs.msg:PointCloud2",
    },
}
TOPICS = CASES["assignment1"]
DOMAIN = 1 + (os.getpid() * 11) % 101


def stamp_of(msg) -> float:
    t = msg.clock if hasattr(msg, "clock") else msg.header.stamp
    return round(t.sec + t.nanosec * 1e-9, 6)


# ---------------------------------------------------------------- the subscriber process


def listen(out: str, case: str) -> None:
    """Subscribes to TOPICS; on SIGINT writes {topic: [[stamp, wall, bytes]...]} to ``out``."""
    import importlib

    import rclpy
    from rclpy.qos import QoSProfile
    from rclpy.serialization import serialize_message

    global TOPICS
    TOPICS = CASES[case]
    rclpy.init()
    node = rclpy.create_node("bench_listener")
    seen: dict[str, list] = {topic: [] for topic in TOPICS}
    sizes: dict[str, int] = {}
    for topic, spec in TOPICS.items():
        module, name = spec.split(":")
        msg_type = getattr(importlib.import_module(module), name)

        def callback(msg, topic=topic):
            seen[topic].append((stamp_of(msg), time.time()))
            if topic not in sizes:
                sizes[topic] = len(serialize_message(msg))

        node.create_subscription(msg_type, topic, callback, QoSProfile(depth=100))
    stop = []
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    while not stop:
        rclpy.spin_once(node, timeout_sec=0.05)
    Path(out).write_text(json.dumps({"seen": seen, "sizes": sizes}))
    node.destroy_node()
    rclpy.shutdown()


# ---------------------------------------------------------------- the cell's side


def run(kind: str, seconds: float, scenario: Path, case: str, realtime: bool = False) -> dict:
    """One run; returns its wall time and, with a subscriber, what it received."""
    from omtp_drake import Cell
    from omtp_drake.ros2.bridge import Ros2Cell
    from omtp_drake.ros2.network import Ros2Network

    network = Ros2Network(DOMAIN)
    network.apply()
    listener, out = None, None
    cell_args = {"robot": ROBOT} if case == "tutorial" else {"scenario": str(scenario)}
    with Cell(**cell_args, realtime=realtime) as cell:
        if kind == "bare":
            start, cpu = time.perf_counter(), time.process_time()
            while cell.time < seconds - 1e-9:
                cell.runtime.advance_to(cell.time + 0.01)
            return {"wall": time.perf_counter() - start, "cpu": time.process_time() - cpu}
        with Ros2Cell(cell, network) as node:
            sent: dict[str, list] = {topic: [] for topic in TOPICS}
            for publisher in node.node.publishers:
                if publisher.topic_name in TOPICS:
                    _record(publisher, sent[publisher.topic_name])
            if kind == "ros2+sub":
                out = tempfile.mktemp(suffix=".json")
                listener = subprocess.Popen(
                    [sys.executable, __file__, "--listen", out, "--case", case], start_new_session=True
                )
                _wait_for_subscribers(node)
            cell.runtime.simulator.ResetStatistics()  # realtime pacing counts from here
            start, cpu = time.perf_counter(), time.process_time()
            end = cell.time + seconds
            while cell.time < end - 1e-9:
                node.step()
            wall, cpu = time.perf_counter() - start, time.process_time() - cpu
            if listener is None:
                return {"wall": wall, "cpu": cpu}
            time.sleep(3.0)  # the subscriber works off what it has queued
            listener.send_signal(signal.SIGINT)
            listener.wait(timeout=60)
    received = json.loads(Path(out).read_text())
    os.unlink(out)
    return {"wall": wall, "cpu": cpu, "sent": sent, **received}


def _record(publisher, log: list) -> None:
    publish = publisher.publish

    def timed(msg):
        log.append((stamp_of(msg), time.time()))
        publish(msg)

    publisher.publish = timed


def _wait_for_subscribers(node) -> None:
    end = time.monotonic() + 120
    publishers = [p for p in node.node.publishers if p.topic_name in TOPICS]
    while not all(p.get_subscription_count() > 0 for p in publishers):
        if time.monotonic() > end:
            raise RuntimeError("the subscriber did not connect within 120 s")
        time.sleep(0.05)


def topic_table(result: dict) -> None:
    head = ("sent", "recv", "msg/s", "KiB")
    print(f"{'topic':36s} " + " ".join(f"{h:>7s}" for h in head) + " latency ms: p50     p95     max")
    missing: list[str] = []
    for topic in TOPICS:
        sent = {s: w for s, w in result["sent"][topic]}
        recv = result["seen"][topic]
        latency = np.array([w - sent[s] for s, w in recv if s in sent]) * 1e3
        span = (recv[-1][1] - recv[0][1]) if len(recv) > 1 else float("nan")
        rate = (len(recv) - 1) / span if len(recv) > 1 else float("nan")
        size = result["sizes"].get(topic, 0) / 1024
        p50, p95, top = np.percentile(latency, [50, 95, 100]) if len(latency) else (np.nan,) * 3
        lost = sorted(set(sent) - {s for s, _ in recv})
        if lost:
            missing.append(f"{topic}: {len(lost)} lost, first at {lost[0]:.2f} s, last at {lost[-1]:.2f} s")
        counts = f"{len(sent):7d} {len(recv):7d} {rate:7.1f} {size:7.1f}"
        print(f"{topic:36s} {counts} {p50:15.2f} {p95:7.2f} {top:7.2f}")
    for line in missing:
        print("  " + line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--realtime", action="store_true", help="pace the run with a subscriber")
    parser.add_argument("--case", choices=sorted(CASES), default="assignment1")
    parser.add_argument("--listen", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    global TOPICS
    TOPICS = CASES[args.case]
    if args.listen:
        return listen(args.listen, args.case)
    scenario = Path(tempfile.mkdtemp()) / "rgbd.yaml"
    scenario.write_text(SCENARIO)
    runs: dict[str, list[dict]] = {"bare": [], "ros2": [], "ros2+sub": []}
    for _ in range(args.repeats):
        for kind, results in runs.items():
            results.append(run(kind, args.seconds, scenario, args.case, realtime=args.realtime and kind == "ros2+sub"))
    per_s = {kind: min(r["wall"] for r in results) / args.seconds for kind, results in runs.items()}
    cpu_s = {kind: min(r["cpu"] for r in results) / args.seconds for kind, results in runs.items()}
    print(f"{args.case}: {args.seconds:g} simulated s, best of {args.repeats}, ROS_DOMAIN_ID={DOMAIN}, loopback")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for kind, wall in per_s.items():
        cpu = cpu_s[kind]
        extra = (
            f"  ({1e3 * (wall - per_s['bare']):+.0f} wall, {1e3 * (cpu - cpu_s['bare']):+.0f} CPU ms)"
            if kind != "bare"
            else ""
        )
        print(f"  {kind:9s} {1e3 * wall:7.0f} wall ms, {1e3 * cpu:5.0f} CPU ms per simulated s{extra}")
    pace = "paced to the wall clock" if args.realtime else "as fast as it runs"
    for i, result in enumerate(runs["ros2+sub"]):
        ms = 1e3 * result["wall"] / args.seconds
        print(f"ros2+sub, run {i + 1} ({pace}, {ms:.0f} wall ms per simulated s):")
        topic_table(result)


if __name__ == "__main__":
    main()
