"""Benchmark of the conveyor spawner: the course's plugin with 5 objects and variances
against today's single-kind spawner (one 0.2 m cube, no variance).

    python bench/bench_spawner.py [--seconds 30] [--period 1.5] [--repeats 2]

lecture7_conveyor's belt at full power, the break beam not stopping it, the deletion
wall recycling the parts; a part every ``--period`` s (not one at a time). The plugin's
five objects are meshes written here (a box, an octagonal crate, a hexagonal nut, a tall
block, a 16-sided disk), each with lateral, yaw and timing variances. Prints per
spawner: the build time, parts spawned per simulated minute and per wall minute, the
real-time factor, and the CPU time per simulated second (the run with the least CPU of
the repeats; on a busy machine the CPU figures are the ones to compare).
"""

from __future__ import annotations

import argparse
import logging
import math
import tempfile
import time
from dataclasses import replace
from pathlib import Path

from omtp_drake.scenario import SpawnerConfig, load_scenario
from omtp_drake.scenario.conveyor_spawner import SpawnObjectConfig
from omtp_drake.sim.runtime import FactoryRuntime

# name -> (sides, across-flats width, height) of a prism about its centre
SHAPES = {"box": (4, 0.2, 0.2), "crate": (8, 0.2, 0.2), "nut": (6, 0.18, 0.08), "block": (4, 0.12, 0.25),
          "disk": (16, 0.24, 0.06)}


def write_prism(path: Path, sides: int, width: float, height: float) -> None:
    r = width / 2 / math.cos(math.pi / sides)
    ring = [(r * math.cos(math.pi / sides + 2 * math.pi * k / sides),
             r * math.sin(math.pi / sides + 2 * math.pi * k / sides)) for k in range(sides)]
    lo, hi = -height / 2, height / 2
    tris = []
    for k in range(sides):
        (ax, ay), (bx, by) = ring[k], ring[(k + 1) % sides]
        tris += [((ax, ay, lo), (bx, by, lo), (bx, by, hi)), ((ax, ay, lo), (bx, by, hi), (ax, ay, hi)),
                 ((0, 0, hi), (ax, ay, hi), (bx, by, hi)), ((0, 0, lo), (bx, by, lo), (ax, ay, lo))]
    lines = ["solid prism"]
    for t in tris:
        lines += ["facet normal 0 0 0", "outer loop", *(f"vertex {x} {y} {z}" for x, y, z in t), "endloop",
                  "endfacet"]
    path.write_text("\n".join(lines + ["endsolid prism"]) + "\n")


def spawners(folder: Path, period: float) -> dict[str, SpawnerConfig]:
    single = SpawnerConfig(xyz=[1.2, 4.0, 1.021], period=period, one_at_a_time=False)
    objects = []
    for name, (sides, width, height) in SHAPES.items():
        write_prism(folder / f"{name}.stl", sides, width, height)
        objects.append(SpawnObjectConfig(
            name=name, mesh_resource=f"package://bench/{name}.stl", mesh_file=str(folder / f"{name}.stl"),
            xyz=[1.2, 4.0, 0.92 + height / 2 + 0.001], lateral_variance=0.2, yaw_variance=math.pi / 2,
            timing_variance=0.5))
    plugin = replace(single, objects=objects, randomization_seed=3)
    return {"single kind (today)": single, "plugin, 5 objects": plugin}


def run(spawner: SpawnerConfig, seconds: float) -> tuple[float, int, float, float]:
    scenario = load_scenario("lecture7_conveyor")
    scenario = replace(scenario, spawner=spawner, part_pool=int(seconds / spawner.period) + 4,
                       deletion_wall=True, conveyor=replace(scenario.conveyor, stop_on_beam=False))
    t0 = time.perf_counter()
    rt = FactoryRuntime(scenario)
    build = time.perf_counter() - t0
    t0, c0 = time.perf_counter(), time.process_time()
    rt.advance_to(seconds)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    spawned = rt.pool.spawn_count
    rt.close()
    return build, spawned, wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--period", type=float, default=1.5)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    with tempfile.TemporaryDirectory() as tmp:
        for label, spawner in spawners(Path(tmp), args.period).items():
            runs = [run(spawner, args.seconds) for _ in range(args.repeats)]
            build, spawned, wall, cpu = min(runs, key=lambda r: r[3])
            print(f"{label:22s} build {build:5.2f} s  spawned {spawned:3d} in {args.seconds:g} s simulated "
                  f"({spawned * 60 / args.seconds:5.1f}/sim min, {spawned * 60 / wall:5.1f}/wall min)  "
                  f"RTF {args.seconds / wall:5.2f}  CPU {1000 * cpu / args.seconds:4.0f} ms/sim s "
                  f"(RTF by CPU {args.seconds / cpu:5.2f})")


if __name__ == "__main__":
    main()
