"""What the sleep check's contact query adds to a run (issue 46, bench/README.md
"What a gate on the sleep check's query would save").

    python bench/sleep_query_cost.py [--at 8] [--repeats 400] [--rounds 3]

Runs ``fill_bin`` to ``--at`` s (parts asleep, the arm on its way), then times, on that
state, with the plant's and SceneGraph's caches made stale before each call (the
plant's positions set again: what a plant step does to them):

* ``step``: the plant's next discrete step (``EvalUniquePeriodicDiscreteUpdate``), alone;
* ``query + step``: SceneGraph's penetration query (as ``PartSleep`` asks it), then the step;
* ``check query + step``: ``PartSleep._touches`` (the query and its Python), then the step;
* ``boxes + step``: a gate made of each body's world box (the arms', cups', belt's and
  two sleeping parts', from ``EvalBodyPoseInWorld``, vectorised with numpy), then the step;
* ``query``, ``boxes``: each alone on stale caches.

Thread CPU (``thread_time``) per call, the median of ``--rounds`` rounds of
``--repeats`` calls, interleaved. The query's pose update is SceneGraph's cache entry that
the step evaluates next at the same state: what the query costs alone, it mostly does
for the step.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from omtp_drake.sim.part_sleep import PartSleep
from omtp_drake.tasks.run import TaskRun, prepare


def _boxes(plant, station):
    """(body, centre, half size) of each body's collision geometry's box, in its frame,
    for the bodies that are neither welded nor parts, and for the parts."""
    from pydrake.geometry import Box, Convex, Cylinder, Role, Sphere

    inspector = station.scene_graph.model_inspector()
    boxes: dict = {}
    for g in inspector.GetAllGeometryIds(Role.kProximity):
        body = plant.GetBodyFromFrameId(inspector.GetFrameId(g))
        if plant.IsAnchored(body):
            continue
        shape, X = inspector.GetShape(g), inspector.GetPoseInFrame(g)
        if isinstance(shape, Box):
            c, h = np.zeros(3), np.array([shape.width(), shape.depth(), shape.height()]) / 2
        elif isinstance(shape, Sphere):
            c, h = np.zeros(3), np.full(3, shape.radius())
        elif isinstance(shape, Cylinder):
            c, h = np.zeros(3), np.array([shape.radius(), shape.radius(), shape.length() / 2])
        elif isinstance(shape, Convex):
            c, size = shape.GetConvexHull().CalcBoundingBox()
            c, h = np.asarray(c), np.asarray(size) / 2
        else:
            c, h = np.zeros(3), np.full(3, 1e6)
        c_B, h_B = X.translation() + X.rotation().matrix() @ c, np.abs(X.rotation().matrix()) @ h
        lo, hi = c_B - h_B, c_B + h_B
        if body.index() in boxes:
            _, lo0, hi0 = boxes[body.index()]
            lo, hi = np.minimum(lo, lo0), np.maximum(hi, hi0)
        boxes[body.index()] = (body, lo, hi)
    return [(b, (lo + hi) / 2, (hi - lo) / 2) for b, lo, hi in boxes.values()]


def _cases(rt) -> tuple[dict, object, np.ndarray]:
    """The timed calls on the run's state, the plant's context and its positions."""
    station, plant = rt.station, rt.station.plant
    context = plant.GetMyMutableContextFromRoot(rt.context)
    sleep = PartSleep(station)
    parts = set(station.parts)
    bodies = _boxes(plant, station)
    movers = [b for b in bodies if b[0].name() not in parts]
    sleepers = [b for b in bodies if b[0].name() in parts][:2]
    stacked = [(np.array([b[1] for b in g]), np.array([b[2] for b in g])) for g in (movers, sleepers)]

    def boxes() -> bool:
        lows, highs = [], []
        for group, (c_B, h_B) in zip((movers, sleepers), stacked):
            X = np.array([plant.EvalBodyPoseInWorld(context, b[0]).GetAsMatrix34() for b in group])
            R, p = X[:, :, :3], X[:, :, 3]
            c_W, h_W = p + np.einsum("nij,nj->ni", R, c_B), np.einsum("nij,nj->ni", np.abs(R), h_B)
            lows.append(c_W - h_W)
            highs.append(c_W + h_W)
        apart = (lows[1][:, None] > highs[0][None]) | (lows[0][None] > highs[1][:, None])
        return not apart.any(axis=2).all()

    def query() -> None:
        plant.get_geometry_query_input_port().Eval(context).ComputePointPairPenetration()

    def step() -> None:
        plant.EvalUniquePeriodicDiscreteUpdate(context)

    cases = {
        "step": step,
        "query + step": lambda: (query(), step()),
        "check query + step": lambda: (sleep._touches(context), step()),
        "boxes + step": lambda: (boxes(), step()),
        "query": query,
        "boxes": boxes,
    }
    return cases, context, plant.GetPositions(context)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--at", type=float, default=8.0)
    parser.add_argument("--repeats", type=int, default=400)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    with TaskRun(prepare("fill_bin")) as run:
        rt = run.runtime
        rt.advance_to(args.at)
        cases, context, q = _cases(rt)
        plant = rt.station.plant
        results: dict[str, list[float]] = {name: [] for name in cases}
        for _ in range(args.rounds):
            for name, call in cases.items():
                total = 0.0
                for _ in range(args.repeats):
                    plant.SetPositions(context, q)  # stale caches, as after a plant step
                    t0 = time.thread_time()
                    call()
                    total += time.thread_time() - t0
                results[name].append(1e6 * total / args.repeats)
    print(f"fill_bin at {args.at:g} s; thread CPU us per call, median of {args.rounds} rounds:")
    for name, values in results.items():
        rounds = ", ".join(f"{v:.0f}" for v in values)
        print(f"  {name:20s} {statistics.median(values):7.1f}   ({rounds})")


if __name__ == "__main__":
    main()
