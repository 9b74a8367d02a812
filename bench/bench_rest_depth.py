"""How deep parts rest in what holds them, per plant step (issue 46, item 4: SAP softens
near-rigid contacts by (threshold x step)^2, so a longer step lets parts sink further).

- ``fill_bin`` seed 0 at its end (ten parts stacked in ``bin_1``): the deepest contact of a
  part with each model it touches and with another part (SceneGraph's point pairs) [mm],
  and the run's CPU time (``time.process_time``, the probes included) [s];
- ``lecture7_conveyor`` at 6 s (parts riding the belt, one at the beam): the deepest
  part-belt contact [mm].

Numbers only, no pass/fail:

    python bench/bench_rest_depth.py [--steps 0.01,0.016,0.02]
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import time

from omtp_drake import FactoryRuntime
from omtp_drake.scenario import load_scenario
from omtp_drake.tasks.run import TaskRun, run_task


def depths(runtime) -> dict[str, float]:
    """The deepest contact [mm] of a part (a model instance called ``object_*``) with each
    kind of other model: ``part`` (another part) or the other model's name."""
    plant = runtime.station.plant
    plant_context = plant.GetMyContextFromRoot(runtime.context)
    query = plant.get_geometry_query_input_port().Eval(plant_context)
    inspector = query.inspector()

    def model(geometry_id) -> str:
        body = plant.GetBodyFromFrameId(inspector.GetFrameId(geometry_id))
        return plant.GetModelInstanceName(body.model_instance())

    worst: dict[str, float] = {}
    for pair in query.ComputePointPairPenetration():
        a, b = model(pair.id_A), model(pair.id_B)
        if not (a.startswith("object_") or b.startswith("object_")):
            continue
        part_a, part_b = a.startswith("object_"), b.startswith("object_")
        other = "part" if part_a and part_b else (b if part_a else a)
        worst[other] = max(worst.get(other, 0.0), 1000.0 * pair.depth)
    return worst


def fill_bin_row(step: float) -> str:
    """``fill_bin`` seed 0 at plant step ``step``: where its parts ended, its CPU time and
    the deepest part contacts at its end."""
    last: dict[str, float] = {}

    def probe(run: TaskRun) -> None:
        last.clear()
        last.update(depths(run.runtime))

    scenario = dataclasses.replace(load_scenario("fill_bin").with_time_step(step), seed=0)
    t0 = time.process_time()
    result = run_task(scenario, on_chunk=probe)
    cpu = time.process_time() - t0
    return (
        f"fill_bin in bins {dict(result.ledger.in_bin)}, {result.sim_time_s:g} simulated s, "
        f"CPU {cpu:.1f} s (probes included); deepest part contact at its end [mm]: {_mm(last)}"
    )


def belt_row(step: float) -> str:
    runtime = FactoryRuntime(load_scenario("lecture7_conveyor").with_time_step(step))
    try:
        runtime.advance_to(6.0)
        return f"lecture7_conveyor at 6 s, deepest part contact [mm]: {_mm(depths(runtime))}"
    finally:
        runtime.close()


def _mm(worst: dict[str, float]) -> str:
    return ", ".join(f"{k} {v:.2f}" for k, v in sorted(worst.items()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", default="0.01,0.016,0.02")
    args = parser.parse_args()
    logging.getLogger("omtp_drake").setLevel(logging.ERROR)
    for step in (float(s) for s in args.steps.split(",")):
        print(f"== {1000 * step:g} ms", flush=True)
        print(f"  {fill_bin_row(step)}", flush=True)
        print(f"  {belt_row(step)}", flush=True)


if __name__ == "__main__":
    main()
