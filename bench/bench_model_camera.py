"""What a student's Gazebo camera costs when nobody reads its images: the group's cell
(tests/fixtures/group_ws) with their wrist camera (tests/fixtures/wrist_camera_edits),
against the same files with the camera's ``<sensor>`` removed (bracket and links kept).
Prints the CPU (process time) of the build, of a Context and of a run with the arms
still, median of ``--repeat`` builds in this process; then the first image read (the
renderer made then) and a later one.

    python bench/bench_model_camera.py [--seconds 5] [--repeat 3]
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from pydrake.systems.analysis import Simulator

from omtp_drake.cell.station import build_station
from omtp_drake.launch import own_cell

FIXTURES = Path(__file__).resolve().parent.parent / "tests" / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
SENSOR = re.compile(r'\s*<gazebo reference="\$\(arg robot_prefix\)wrist_camera_link">.*?</gazebo>', re.S)


def _workspace(root: Path, sensor: bool) -> Path:
    src = root / ("camera" if sensor else "no_sensor") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    shutil.copytree(FIXTURES / "wrist_camera_edits", src, dirs_exist_ok=True)
    if not sensor:
        xacro = src / "omtp_support" / "urdf" / "robot_system" / "robot_system.xacro"
        xacro.write_text(SENSOR.sub("", xacro.read_text()))
    return src


def measure(workspace: Path, seconds: float, repeat: int) -> dict[str, float]:
    scenario = own_cell(LAUNCH, workspace=[workspace], environ={}).scenario
    rows: dict[str, list[float]] = {"build": [], "context": [], "run": []}
    for _ in range(repeat):
        t0 = time.process_time()
        station = build_station(scenario)
        t1 = time.process_time()
        context = station.create_context()
        t2 = time.process_time()
        Simulator(station.diagram, context).AdvanceTo(seconds)
        t3 = time.process_time()
        for key, value in (("build", t1 - t0), ("context", t2 - t1), ("run", t3 - t2)):
            rows[key].append(value)
    result = {key: statistics.median(values) for key, values in rows.items()}
    for name in station.depth_cameras:
        port = station.diagram.GetOutputPort(f"{name}.color_image")
        t0 = time.process_time()
        port.Eval(context)
        result["first read"] = time.process_time() - t0
        Simulator(station.diagram, context).AdvanceTo(seconds + 0.5)
        t0 = time.process_time()
        port.Eval(context)
        result["a later read"] = time.process_time() - t0
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="omtp_bench_camera_") as folder:
        for sensor in (True, False):
            row = measure(_workspace(Path(folder), sensor), args.seconds, args.repeat)
            label = "wrist camera, unread" if sensor else "no <sensor>         "
            print(label, "  ".join(f"{key} {value:.2f} s" for key, value in row.items()))


if __name__ == "__main__":
    main()
