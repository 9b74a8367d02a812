"""Cost of one logical-camera update (the camera's own work, not the plant's).

Builds a plant with 20 free 0.1 m boxes inside the view of the course's camera 1
(on the belt under it) and 10 outside it (far down the belt), then times one
update through the system API (``CalcForcedUnrestrictedUpdate``) with the plant's
body poses already cached, so only the camera's own work is measured. Cases:

* ``centres in view``: the boxes' centres are inside the frustum (the cheap tests
  decide every box);
* ``straddling far``: the boxes cross the far plane with their centres beyond it
  (every box in view needs the full 26-axis test);
* each with and without noise.

Also printed: pydrake's conversion of the ``body_poses`` input to a Python list,
part of every update and proportional to the plant's number of bodies.
Prints, in microseconds, the fastest and the median of several runs (on a busy
machine the fastest is the better estimate of the cost itself); no pass/fail.
"""

import statistics
import sys
import time
from pathlib import Path
from typing import Callable

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from pydrake.geometry import Box, ProximityProperties  # noqa: E402
from pydrake.math import RigidTransform, RollPitchYaw  # noqa: E402
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph  # noqa: E402
from pydrake.multibody.tree import FixedOffsetFrame, SpatialInertia  # noqa: E402
from pydrake.systems.framework import DiagramBuilder  # noqa: E402

from omtp_drake.cell.logical_camera import add_logical_camera  # noqa: E402
from omtp_drake.scenario import LogicalCameraConfig

IN_VIEW = 20
OUT_OF_VIEW = 10
ITERATIONS = 1000
RUNS = 9
SIZE = 0.1


def _time_us(fn: Callable[[], object]) -> tuple[float, float]:
    """(fastest, median) over RUNS of the mean time of one call over ITERATIONS calls [us]."""
    for _ in range(100):
        fn()
    runs = []
    for _ in range(RUNS):
        start = time.perf_counter()
        for _ in range(ITERATIONS):
            fn()
        runs.append((time.perf_counter() - start) / ITERATIONS * 1e6)
    return min(runs), statistics.median(runs)


def _bench(box_z: float, sigma: float
           ) -> tuple[int, int, tuple[float, float], tuple[float, float]]:
    """(models seen, bodies, us per update, us per body_poses conversion)."""
    config = LogicalCameraConfig(name="logical_camera_1", xyz=[1.2, 1.8, 2.0],
                                 rpy=[0.0, 1.5708, 0.0], position_noise_sigma=sigma,
                                 orientation_noise_sigma=10 * sigma)
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    bodies = []
    for i in range(IN_VIEW + OUT_OF_VIEW):
        instance = plant.AddModelInstance(f"object_{i}")
        body = plant.AddRigidBody("base", instance,
                                  SpatialInertia.SolidBoxWithMass(1.0, SIZE, SIZE, SIZE))
        plant.RegisterCollisionGeometry(body, RigidTransform(), Box(SIZE, SIZE, SIZE),
                                        "collision", ProximityProperties())
        bodies.append(body)
    frame = plant.AddFrame(FixedOffsetFrame("logical_camera_1_frame", plant.world_frame(),
                                            config.X_PC()))
    plant.Finalize()
    camera = add_logical_camera(builder, plant, scene_graph, frame, config)
    diagram = builder.Build()
    root = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(root)
    for i, body in enumerate(bodies):
        # In view: a 4 x 5 grid under the camera; out of view: far down the belt.
        xy = ([1.05 + 0.1 * (i % 4), 1.6 + 0.1 * (i // 4)] if i < IN_VIEW
              else [1.2, -3.0 - 0.2 * i])
        plant.SetFreeBodyPose(plant_context, body,
                              RigidTransform(RollPitchYaw(0, 0, 0.1 * i), [*xy, box_z]))
    context = camera.GetMyMutableContextFromRoot(root)
    state = context.get_mutable_state()
    camera.CalcForcedUnrestrictedUpdate(context, state)
    seen = len(state.get_abstract_state(0).get_value().models)
    update_us = _time_us(lambda: camera.CalcForcedUnrestrictedUpdate(context, state))
    port = camera.get_input_port(0)
    poses_us = _time_us(lambda: port.Eval(context))
    return seen, plant.num_bodies(), update_us, poses_us


def main() -> None:
    # Camera at z = 2.0, far = 1.0: the far plane is at z = 1.0.
    cases = {"centres in view": 1.02, "straddling far": 0.97}
    print(f"{'case':<16} {'noise':>6} {'seen':>5} {'bodies':>6} "
          f"{'update_us min/median':>21} {'body_poses_us min/median':>25}")
    for label, box_z in cases.items():
        for sigma in (0.0, 0.001):
            seen, bodies, update_us, poses_us = _bench(box_z, sigma)
            print(f"{label:<16} {sigma:>6} {seen:>5} {bodies:>6} "
                  f"{update_us[0]:>11.1f} / {update_us[1]:>6.1f} "
                  f"{poses_us[0]:>15.1f} / {poses_us[1]:>6.1f}")


if __name__ == "__main__":
    main()
