"""The physical limit: the bare plant of a scenario next to the full run of it.

Bare plant: the scenario's MultibodyPlant and SceneGraph (the same bodies,
geometries, contact model, time step and parked pool, from
``station.add_cell_models``), each arm held at its initial pose by the same servo
(interpolator + inverse dynamics, fed by a constant: C++ only), the belt at its
speed. None of our Python systems (cameras, grippers, beam, belt, controller,
driver). Full: the same scenario run as users run it.

Cases (wall ms per simulated second; lower is better):
- ``fill_bin``: full = ``run_task("fill_bin")`` (10 parts); bare = holding still
  with one part on the floor.
- ``lecture7_conveyor_pick``: full = its task (2 parts); bare = one part on the belt.
- ``lecture7_conveyor`` with 10 parts riding the belt (the beam stop off): full =
  ``FactoryRuntime``; bare = the same parts on the same belt.

Prints both and our overhead in percent. Best of ``--repeats``.

    python bench/bench_bare.py [--repeats 3] [--seconds 10]
"""

from __future__ import annotations

import argparse
import logging
import time
from dataclasses import replace

import numpy as np
from pydrake.math import RigidTransform
from pydrake.multibody.plant import AddMultibodyPlant
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from omtp_drake import arms
from omtp_drake.conveyor import MAX_SPEED
from omtp_drake.parts import PartConfig
from omtp_drake.runtime import FactoryRuntime
from omtp_drake.scenario import Scenario, load_scenario
from omtp_drake.station import add_cell_models
from omtp_drake.tasks import run_task

logging.getLogger("drake").setLevel(logging.ERROR)
logging.getLogger("omtp_drake").setLevel(logging.WARNING)

BELT_Z = 0.92 + 0.1 + 0.001  # a 0.2 m part resting on the belt


def bare_run(scenario: Scenario, seconds: float) -> float:
    """Wall seconds per simulated second of the scenario's bare plant."""
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(scenario.plant_config, builder)
    plant.mutable_gravity_field().set_gravity_vector(scenario.gravity)
    models = add_cell_models(plant, scene_graph, scenario)
    plant.Finalize()
    for handles in models.arms.values():
        q = arms.named_pose(handles.config.initial_pose, handles.config)
        interpolator, _, handles.control_plant = arms.add_arm_controller(
            builder, plant, handles.arm, handles.config, scenario.gravity)
        handles.interpolator = interpolator
        source = builder.AddSystem(ConstantVectorSource(q))
        builder.Connect(source.get_output_port(), interpolator.get_input_port())
    if models.conveyor is not None:
        power = scenario.conveyor.power if scenario.conveyor else 0.0
        belt = builder.AddSystem(ConstantVectorSource([0.0, -MAX_SPEED * power / 100.0]))
        builder.Connect(belt.get_output_port(), plant.get_desired_state_input_port(models.conveyor))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    for handles in models.arms.values():
        q = arms.named_pose(handles.config.initial_pose, handles.config)
        plant.SetPositions(plant_context, handles.arm, q)
        handles.interpolator.set_initial_position(
            handles.interpolator.GetMyMutableContextFromRoot(context), q)
    for name in models.pool:
        (index,) = plant.GetJointIndices(models.parts[name])
        plant.get_joint(index).Lock(plant_context)
    simulator = Simulator(diagram, context)
    simulator.Initialize()
    start = time.perf_counter()
    simulator.AdvanceTo(seconds)
    return (time.perf_counter() - start) / seconds


def with_parts(scenario: Scenario, xyzs: list[list[float]], size: float) -> Scenario:
    parts = [PartConfig(name=f"bench_{k}", xyz=list(p), size=size, mass=0.2) for k, p in enumerate(xyzs)]
    return replace(scenario, parts=parts, spawner=None, task=None)


def conveyor_scenario() -> Scenario:
    s = load_scenario("lecture7_conveyor")
    return replace(s, conveyor=replace(s.conveyor, stop_on_beam=False, power=100.0))


def full_conveyor(seconds: float) -> float:
    """lecture7_conveyor, 10 parts riding the belt, every system of ours on."""
    s = with_parts(conveyor_scenario(), [[1.2, 4.6 - 0.45 * k, BELT_Z] for k in range(10)], 0.2)
    rt = FactoryRuntime(replace(s, part_pool=0))
    start = time.perf_counter()
    rt.advance_to(seconds)
    return (time.perf_counter() - start) / seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0, help="simulated seconds of a bare run")
    args = parser.parse_args()
    fill = load_scenario("fill_bin")
    pick = load_scenario("lecture7_conveyor_pick")
    cases = {
        "fill_bin (10 parts)": (
            lambda: bare_run(with_parts(fill, [[-8.3, -1.23, 0.051]], fill.pool_part_size), args.seconds),
            lambda: _task_ms(run_task("fill_bin"))),
        "lecture7_conveyor_pick (2 parts)": (
            lambda: bare_run(with_parts(pick, [[1.2, 1.8, BELT_Z]], 0.2), args.seconds),
            lambda: _task_ms(run_task("lecture7_conveyor_pick"))),
        "lecture7_conveyor, 10 parts on the belt": (
            lambda: bare_run(with_parts(conveyor_scenario(), [[1.2, 4.6 - 0.45 * k, BELT_Z]
                                                              for k in range(10)], 0.2), args.seconds),
            lambda: full_conveyor(args.seconds)),
    }
    print(f"{'case':<42} {'bare ms/s':>10} {'full ms/s':>10} {'overhead':>9} {'full RTF':>9}")
    for label, (bare, full) in cases.items():
        b = min(bare() for _ in range(args.repeats))
        f = min(full() for _ in range(args.repeats))
        print(f"{label:<42} {1e3 * b:10.1f} {1e3 * f:10.1f} {100 * (f - b) / b:8.0f} % {1 / f:9.1f}")


def _task_ms(result) -> float:
    if not result.success:
        raise RuntimeError(f"{result.scenario} did not succeed: {result.summary}")
    return result.wall_time_s / result.sim_time_s


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
