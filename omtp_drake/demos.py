"""Ready-made runs of the factory, used by the command line and the benchmarks."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Optional

from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import TrajectorySource

from omtp_drake.cell import arms
from omtp_drake.cell.station import Station
from omtp_drake.scenario import Scenario, as_scenario
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.viz.meshcat import save_recording, start_meshcat, start_recording

_log = logging.getLogger(__name__)

#: The tour of the named-pose demo.
TOUR = ("Home", "PreGrasp", "Place", "Home")


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
    tour: tuple[str, ...] = TOUR,
) -> RunStats:
    """Both arms move through their named poses (Home, PreGrasp, Place, Home),
    in any scenario (its spawner, belt and grippers run as usual, vacuum off)."""
    t0 = time.perf_counter()
    scenario = as_scenario(scenario)
    robots = {r.name: r for r in scenario.robots}
    for robot in robots.values():
        arms.named_pose(tour[0], robot)  # a bad pose name: one clear error before building
    scenario = _starting_at(scenario, tour[0])
    viewer = start_meshcat() if (meshcat or record) else None
    end = 0.0

    def drive_arms(builder: DiagramBuilder, station: Station) -> None:
        nonlocal end
        for name, handles in station.arms.items():
            trajectory = arms.joint_trajectory(handles.config, list(tour))
            source = builder.AddNamedSystem(f"{name}.tour", TrajectorySource(trajectory))
            builder.Connect(source.get_output_port(), station.diagram.GetInputPort(f"{name}.position"))
            end = max(end, trajectory.end_time())

    runtime = FactoryRuntime(scenario, meshcat=viewer, extend=drive_arms)
    build_time = time.perf_counter() - t0
    if record:
        start_recording(runtime.station.visualizer)
    t1 = time.perf_counter()
    runtime.advance_to(end)
    wall = time.perf_counter() - t1
    if record:
        save_recording(runtime.station.visualizer, viewer, record)
    return RunStats(sim_time_s=end, wall_time_s=wall, build_time_s=build_time)


def _starting_at(scenario: Scenario, pose: str) -> Scenario:
    """The scenario with every arm's initial pose at ``pose``."""
    return replace(scenario, robots=[replace(r, initial_pose=pose) for r in scenario.robots])
