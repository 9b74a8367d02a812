"""Ready-made runs of the factory, used by the command line and the notebooks."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import TrajectorySource

from omtp_drake import arms
from omtp_drake.scenario import Scenario, load_scenario
from omtp_drake.station import build_station
from omtp_drake.visualization import save_recording, start_meshcat, start_recording

_log = logging.getLogger(__name__)

#: The tour of the named-pose demo.
TOUR = ["Home", "PreGrasp", "Place", "Home"]


@dataclass
class RunStats:
    sim_time_s: float
    wall_time_s: float
    build_time_s: float

    @property
    def real_time_factor(self) -> float:
        return self.sim_time_s / self.wall_time_s if self.wall_time_s > 0 else float("inf")


def named_pose_tour(
    scenario: Scenario | str = "omtp_factory",
    *,
    meshcat: bool = False,
    record: Optional[str | Path] = None,
    tour: list[str] = TOUR,
) -> RunStats:
    """Both arms move through their named poses (Home, PreGrasp, Place, Home)."""
    t0 = time.perf_counter()
    if not isinstance(scenario, Scenario):
        scenario = load_scenario(scenario)
    viewer = start_meshcat() if (meshcat or record) else None
    station = build_station(scenario, meshcat=viewer)
    builder = DiagramBuilder()
    builder.AddSystem(station.diagram)
    end = 0.0
    for name, handles in station.arms.items():
        trajectory = arms.joint_trajectory(handles.config, tour)
        source = builder.AddNamedSystem(f"{name}.tour", TrajectorySource(trajectory))
        builder.Connect(source.get_output_port(), station.diagram.GetInputPort(f"{name}.position"))
        end = max(end, trajectory.end_time())
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    for name, handles in station.arms.items():
        station.set_arm_positions(context, name, arms.named_pose(tour[0], handles.config))
    simulator = Simulator(diagram, context)
    simulator.Initialize()
    build_time = time.perf_counter() - t0
    if record:
        start_recording(station.visualizer)
    t1 = time.perf_counter()
    simulator.AdvanceTo(end)
    wall = time.perf_counter() - t1
    if record:
        save_recording(station.visualizer, viewer, record)
    return RunStats(sim_time_s=end, wall_time_s=wall, build_time_s=build_time)
