"""Cost of a Gazebo depth camera (``libgazebo_ros_camera.so`` on a ``depth`` sensor) per
simulated second: the URDF tutorial's robot (tests/fixtures/tutorial_ws) with its
640 x 480, 20 Hz depth camera, in Gazebo's empty world.

Cases, each simulated ``--seconds`` (default 2) with ``FactoryRuntime`` (the driver's
50 ms ticks), interleaved ``--repeats`` times (best of, CPU and wall):

* ``no camera``: the same robot with its sensor removed (the plant alone);
* ``camera``: the sensor rendered at 20 Hz (colour + depth by VTK, colour noise);
* ``camera + topics``: also what ``ros-run`` publishes per image when a script
  subscribes: image_raw, depth/image_raw and points (the point cloud and its
  PointCloud2), built once per image.

Printed: CPU and wall seconds per simulated second per case, and the camera's share
(``camera`` minus ``no camera``), per image. Numbers only; no pass/fail.

    python bench/bench_rgbd.py [--repeats 3] [--seconds 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from omtp_drake.scenario import with_robot  # noqa: E402
from omtp_drake.sim.runtime import FactoryRuntime  # noqa: E402

ROBOT = Path(__file__).resolve().parent.parent / "tests/fixtures/tutorial_ws/src/slider_arm_description/urdf"
ROBOT = ROBOT / "slider_arm.urdf.xacro"


def _scenario(camera: bool):
    scenario = with_robot(None, ROBOT)
    if camera:
        return scenario
    (model,) = scenario.models
    tags = dataclasses.replace(model.gazebo, sensors=[])
    return dataclasses.replace(scenario, models=[dataclasses.replace(model, gazebo=tags)])


def _run(case: str, seconds: float) -> tuple[float, float]:
    """(CPU s, wall s) per simulated second of ``case`` (the build not counted)."""
    runtime = FactoryRuntime(_scenario(case != "no camera"))
    if case == "camera + topics":
        from omtp_drake.gazebo.camera import camera_publications, camera_views
        from omtp_drake.ros.gazebo.plugin_topics import to_ros1

        class _Cell:  # what the camera plugin reads of a Cell
            station, scenario = runtime.station, runtime.scenario

        cell = _Cell()
        cell.runtime = runtime
        (view,) = camera_views(cell)
        wanted = ("/image_raw", "/depth/image_raw", "/points")
        topics = [p for p in camera_publications(cell, view) if p.topic.endswith(wanted)]

        def publish(rt: FactoryRuntime) -> None:
            for t in topics:
                for message in t.poll(rt.time):
                    to_ros1(message)

        runtime.on_tick(publish)
    cpu, wall = time.process_time(), time.perf_counter()
    runtime.advance_to(seconds)
    return (time.process_time() - cpu) / seconds, (time.perf_counter() - wall) / seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=2.0)
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    cases = ["no camera", "camera", "camera + topics"]
    best = {case: (float("inf"), float("inf")) for case in cases}
    for _ in range(args.repeats):
        for case in cases:
            cpu, wall = _run(case, args.seconds)
            best[case] = (min(best[case][0], cpu), min(best[case][1], wall))
    print(f"tutorial robot, depth camera 640 x 480, 20 Hz, {args.seconds:g} s, best of {args.repeats}")
    for case in cases:
        print(f"  {case:16s} CPU {best[case][0]:6.3f} s   wall {best[case][1]:6.3f} s   per simulated second")
    for case in cases[1:]:
        cpu = best[case][0] - best["no camera"][0]
        per_image = cpu / 20 * 1e3
        print(f"  {case} - no camera: {cpu:.3f} CPU s per simulated second = {per_image:.1f} ms per image")


if __name__ == "__main__":
    main()
