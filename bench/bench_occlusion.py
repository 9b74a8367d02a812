"""Cost of the logical camera's occlusion test, and of the alternative it beat.

1. Cost per camera sample: ``omtp_factory`` with 20 parts (0.1 m cubes, a 5 x 4
   grid on the floor) in the view of logical camera 2, robot 2 at PreGrasp (its
   wrist and gripper in view too), one camera update through the system API
   (``CalcForcedUnrestrictedUpdate``) right after a change of the plant's state
   (so the body poses are recomputed, as in a simulation): occlusion off, and
   on (rays cast against the visual geometry, ``OCCLUSION_GRID`` ^ 2 rays per
   model). For comparison, what the other design would pay for its label image
   alone: ``QueryObject.RenderLabelImage`` by VTK at the camera's pose after the
   same state change, at 64 x 36 and 160 x 90 pixels (camera 2's aspect ratio),
   before any model's unoccluded projection is computed.

2. The real-time factor of the ``fill_bin`` task (``run_task("fill_bin",
   parts=3)``) with camera 2's occlusion off and on (10 Hz; target: on costs at
   most 15 %), best of ``--repeats`` interleaved runs each; wall and CPU time
   (``process_time``, less sensitive to other load on the machine), and the
   time the occlusion test itself takes as a share of the run (the cost that
   the others measure through the machine's noise).

Prints numbers only; no pass/fail.

    python bench/bench_occlusion.py [--repeats 3] [--parts 3] [--skip-task]
"""

from __future__ import annotations

import argparse
import logging
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import replace
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import numpy as np  # noqa: E402
from pydrake.geometry import ClippingRange, ColorRenderCamera, QueryObject, RenderCameraCore  # noqa: E402
from pydrake.math import RigidTransform  # noqa: E402
from pydrake.systems.framework import Context  # noqa: E402

from omtp_drake.cell.occlusion import OCCLUSION_GRID  # noqa: E402
from omtp_drake.cell.logical_camera import X_CameraOptical  # noqa: E402
from omtp_drake.cell.rgbd import RENDERER_NAME, camera_info  # noqa: E402
from omtp_drake.cell.station import Station, build_station  # noqa: E402
from omtp_drake.scenario import PartConfig, Scenario, load_scenario  # noqa: E402
from omtp_drake.tasks.run import TaskRun, run_task  # noqa: E402

CAMERA = "logical_camera_2"
RUNS = 7
ITERATIONS = 40


def _with_camera(scenario: Scenario, **changes) -> Scenario:
    """``scenario`` with ``changes`` to camera 2's configuration."""
    cameras = [replace(c, **changes) if c.name == CAMERA else c for c in scenario.cameras]
    return replace(scenario, cameras=cameras)


def _scene(occlusion: bool, rgbd: bool = False) -> Scenario:
    """omtp_factory, robot 2 at PreGrasp over 20 parts under camera 2."""
    scenario = load_scenario("omtp_factory")
    scenario.robots = [
        replace(r, initial_pose="PreGrasp") if r.name == "robot2" else r for r in scenario.robots
    ]
    k = 0
    for dx in (-0.27, -0.09, 0.09, 0.27):
        for dy in (-0.48, -0.24, 0.0, 0.24, 0.48):
            k += 1
            xyz = [-8.3 + dx, -1.23 + dy, 0.051]
            scenario.parts.append(PartConfig(name=f"object_{k}", xyz=xyz, size=0.1))
    return _with_camera(scenario, occlusion=occlusion, rgbd=rgbd)


def _time_ms(fn: Callable[[], object], perturb: Callable[[], None]) -> tuple[float, float]:
    """(fastest, median) over RUNS of the mean time of ``fn()`` after ``perturb()`` [ms]."""
    for _ in range(3):
        perturb()
        fn()
    runs = []
    for _ in range(RUNS):
        total = 0.0
        for _ in range(ITERATIONS):
            perturb()
            start = time.perf_counter()
            fn()
            total += time.perf_counter() - start
        runs.append(total / ITERATIONS * 1e3)
    return min(runs), statistics.median(runs)


def _perturber(station: Station, context: Context) -> Callable[[], None]:
    """Nudges robot 2's first joint by +-1e-9 rad: a new state, the same scene."""
    plant = station.plant
    plant_context = plant.GetMyMutableContextFromRoot(context)
    arm = station.arm("robot2").arm
    q0 = plant.GetPositions(plant_context, arm)
    sign = [1.0]

    def perturb() -> None:
        sign[0] = -sign[0]
        plant.SetPositions(plant_context, arm, q0 + [sign[0] * 1e-9, 0, 0, 0, 0, 0])

    return perturb


def sample_costs() -> None:
    print(f"1. one sample of {CAMERA}, 20 parts and robot 2's wrist in view "
          f"({OCCLUSION_GRID} x {OCCLUSION_GRID} rays per model)")
    print(f"{'case':<34} {'reported':>8} {'ms min / median':>17}")
    reported: dict[bool, set[str]] = {}
    for occlusion in (False, True):
        station = build_station(_scene(occlusion))
        context = station.create_context()
        camera = station.cameras[CAMERA]
        camera_context = camera.GetMyMutableContextFromRoot(context)
        state = camera_context.get_mutable_state()
        perturb = _perturber(station, context)
        cost = _time_ms(partial(camera.CalcForcedUnrestrictedUpdate, camera_context, state), perturb)
        image = camera.get_output_port().Eval(camera_context)
        label = "occlusion on (ray casts)" if occlusion else "occlusion off"
        print(f"{label:<34} {len(image.models):>8} {cost[0]:>8.2f} / {cost[1]:>6.2f}")
        reported[occlusion] = {m.name for m in image.models}
        if occlusion:
            partly = [(m.name, round(m.visible_fraction, 2)) for m in image.models
                      if m.visible_fraction < 0.99]
            print(f"{'':<34} partly hidden: {partly}; "
                  f"not reported: {sorted(reported[False] - reported[True])}")

    station = build_station(_scene(False, rgbd=True))  # adds the VTK renderer
    context = station.create_context()
    config = station.cameras[CAMERA].config
    frame = station.plant.GetFrameByName(f"{CAMERA}_frame")
    plant_context = station.plant.GetMyContextFromRoot(context)
    X_WO = frame.CalcPoseInWorld(plant_context) @ X_CameraOptical()
    world = station.scene_graph.world_frame_id()
    query_port = station.diagram.GetOutputPort("query_object")
    station_context = station.diagram.GetMyContextFromRoot(context)
    perturb = _perturber(station, context)
    for width in (64, 160):
        sized = replace(config, rgbd_width=width)
        # The label image an occlusion test would use: clipped at the frustum's near and far.
        core = RenderCameraCore(RENDERER_NAME, camera_info(sized), ClippingRange(config.near, config.far),
                                RigidTransform())
        label_camera = ColorRenderCamera(core, False)

        def render(color: ColorRenderCamera = label_camera) -> None:
            query: QueryObject = query_port.Eval(station_context)
            query.RenderLabelImage(color, world, X_WO)

        cost = _time_ms(render, perturb)
        label = f"label render only, {width} x {sized.rgbd_height()}"
        print(f"{label:<34} {'':>8} {cost[0]:>8.2f} / {cost[1]:>6.2f}")


def task_rtf(repeats: int, parts: int) -> None:
    print(f"\n2. fill_bin, {parts} parts, {CAMERA} at 10 Hz; runs interleaved, best of {repeats}")
    print(f"{'occlusion':>9} {'result':>8} {'sim s':>6} {'wall s':>7} {'RTF':>6} {'cpu s':>7} "
          f"{'RTF(cpu)':>8} {'occlusion s':>11}")
    best: dict[bool, list[tuple[float, float]]] = {False: [], True: []}
    share = []
    base = load_scenario("fill_bin")
    for _ in range(repeats):
        for occlusion in (False, True):
            spent = [0.0]

            def time_occlusion(run: TaskRun, spent: list[float] = spent) -> None:
                # The occlusion test's own time: wrap the camera's visibility test.
                visibility = run.runtime.station.cameras[CAMERA]._visibility
                fractions = visibility.fractions

                def timed(*args, spent: list[float] = spent):
                    start = time.perf_counter()
                    result = fractions(*args)
                    spent[0] += time.perf_counter() - start
                    return result

                visibility.fractions = timed

            cpu0 = time.process_time()
            result = run_task(_with_camera(base, occlusion=occlusion), parts=parts, on_start=time_occlusion)
            cpu = time.process_time() - cpu0
            sim, wall = result.summary["sim_time_s"], result.summary["wall_time_s"]
            best[occlusion].append((sim / wall, sim / cpu))
            if occlusion:
                share.append(spent[0] / wall)
            print(f"{'on' if occlusion else 'off':>9} {'ok' if result.success else 'FAILED':>8} {sim:6.1f} "
                  f"{wall:7.2f} {sim / wall:6.2f} {cpu:7.2f} {sim / cpu:8.2f} {spent[0]:11.3f}")
    for label, k in (("wall", 0), ("cpu", 1)):
        off, on = max(r[k] for r in best[False]), max(r[k] for r in best[True])
        print(f"occlusion costs {(off - on) / off * 100:.1f} % of the real-time factor "
              f"({label}, best runs; target <= 15 %)")
    print(f"the occlusion test's own time: {100 * min(share):.1f} % of the run's wall time "
          f"(the change of the real-time factor it causes, without the machine's noise)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--parts", type=int, default=3)
    parser.add_argument("--skip-task", action="store_true", help="only the cost per sample")
    args = parser.parse_args()
    logging.getLogger("drake").setLevel(logging.ERROR)
    np.set_printoptions(precision=3)
    sample_costs()
    if not args.skip_task:
        task_rtf(args.repeats, args.parts)


if __name__ == "__main__":
    main()
