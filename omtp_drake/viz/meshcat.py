"""Meshcat: live views and standalone HTML replays of a simulation."""

from __future__ import annotations

import gc
import logging
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import numpy as np
from pydrake.geometry import Meshcat, MeshcatVisualizer, Rgba, Sphere
from pydrake.math import RigidTransform
from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError

if TYPE_CHECKING:
    from omtp_drake.cell.station import Station
    from omtp_drake.scenario import LogicalCameraConfig, Scenario
    from omtp_drake.sim.runtime import FactoryRuntime

_log = logging.getLogger(__name__)

#: Default eye and target of the Meshcat camera (world): the whole cell, from
#: beside the conveyor, looking toward robot 2 and bin 1.
DEFAULT_VIEW = ((4.0, 5.5, 4.5), (-3.0, -0.5, 0.5))


def start_meshcat(view: tuple[Sequence[float], Sequence[float]] = DEFAULT_VIEW) -> Meshcat:
    """Starts Drake's Meshcat server (localhost) and aims its camera at ``view``."""
    meshcat = Meshcat()
    eye, target = view
    meshcat.SetCameraPose(list(eye), list(target))
    _log.info("Meshcat is at %s", meshcat.web_url())
    return meshcat


def free_meshcats_here() -> None:
    """Frees, now and on this thread, the garbage cycles that may hold a Meshcat.

    Drake's Meshcat must be destroyed on the thread that made it (else the process aborts:
    ``IsThread(main_thread_id_)`` in meshcat.cc), and a cell that held one is freed by
    Python's cycle collector on whichever thread happens to trigger it. Call this before
    starting a thread of Python code (a Dask client's event loop, rclpy's executor), so
    the cells dropped on this thread are freed here, not there."""
    gc.collect()


def start_recording(visualizer: MeshcatVisualizer) -> None:
    """Records every published frame for a replay (no live updates meanwhile)."""
    visualizer.StartRecording(set_transforms_while_recording=False)


def save_recording(visualizer: MeshcatVisualizer, meshcat: Meshcat, path: str | Path) -> Path:
    """Ends the recording and writes a standalone HTML replay to ``path``."""
    visualizer.StopRecording()
    visualizer.PublishRecording()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(meshcat.StaticHtml())
    _log.info("replay written to %s (%.1f MB)", path, path.stat().st_size / 1e6)
    return path


# ----------------------------------------------------------------------------- views

#: Offset of the eye from the interesting spot (world): from -x (for robot 2, the
#: pick spot in front, the arm in the middle, the bin to the right), and above.
_EYE_OFFSET = np.array([-1.7, 0.3, 1.15])


def view_for(scenario: Scenario) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """(eye, target) of the Meshcat camera for ``scenario``: its task robot, the
    bin it fills and the spot it picks from (its pick camera); without a task,
    its first placed part and the nearest robot; else :data:`DEFAULT_VIEW`."""
    from omtp_drake.cell import arms

    robots = {r.name: r for r in scenario.robots}
    cameras = {c.name: c for c in scenario.cameras}
    bins = {b.name: b for b in scenario.bins}
    spots: list[np.ndarray] = []
    task = scenario.task
    if task is not None and task.robot in robots:
        spots.append(arms.base_pose(robots[task.robot]).translation())
        if task.bin in bins:
            spots.append(np.asarray(bins[task.bin].xyz, dtype=float) + [0.0, 0.0, 0.3])
        if task.camera in cameras and cameras[task.camera].parent == "world":
            xyz = np.asarray(cameras[task.camera].xyz, dtype=float)
            spots.append(np.array([xyz[0], xyz[1], 0.5]))
    elif scenario.parts and robots:
        part = np.asarray(scenario.parts[0].xyz, dtype=float)
        nearest = min(robots.values(), key=lambda r: float(np.hypot(*(np.asarray(r.xy) - part[:2]))))
        spots += [part, arms.base_pose(nearest).translation()]
    if not spots:
        return DEFAULT_VIEW
    target = np.mean(spots, axis=0)
    target[2] = min(max(target[2], 0.3), 1.0)
    spread = max(float(np.max(np.linalg.norm(np.array(spots)[:, :2] - target[:2], axis=1))), 0.5)
    eye = target + _EYE_OFFSET * max(1.0, spread / 0.8)
    return tuple(float(v) for v in eye), tuple(float(v) for v in target)


# ----------------------------------------------------------------------------- extras

#: Colour of the logical cameras' frusta and of the detection markers.
FRUSTUM_RGBA = Rgba(1.0, 0.55, 0.0, 1.0)
MARKER_RGBA = Rgba(1.0, 0.2, 0.8, 1.0)


def frustum_segments(config: LogicalCameraConfig) -> tuple[np.ndarray, np.ndarray]:
    """(start, end), each 3 x 12: the edges of a logical camera's view frustum in
    its camera frame C (view along +Cx, horizontal field of view about Cz)."""
    corners = []
    for d in (config.near, config.far):
        half_y = d * math.tan(config.horizontal_fov / 2)
        half_z = half_y / config.aspect_ratio
        corners.append(
            [np.array([d, sy * half_y, sz * half_z]) for sy, sz in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
        )
    near, far = corners
    edges = [(a[i], a[(i + 1) % 4]) for a in (near, far) for i in range(4)]
    edges += [(near[i], far[i]) for i in range(4)]
    start = np.array([e[0] for e in edges]).T
    end = np.array([e[1] for e in edges]).T
    return start, end


def draw_frusta(
    meshcat: Meshcat,
    station: Station,
    root_context: Context,
    *,
    path: str = "/frusta",
    rgba: Rgba = FRUSTUM_RGBA,
) -> list[str]:
    """Draws each logical camera's view frustum as a wireframe at ``<path>/<camera>``
    (toggle them in Meshcat's controls), at the camera's pose in ``root_context``.
    Static objects: they are part of a recorded replay too. Returns the paths."""
    plant = station.plant
    plant_context = plant.GetMyContextFromRoot(root_context)
    paths = []
    for name, camera in sorted(station.cameras.items()):
        config = camera.config
        X_WP = plant.GetFrameByName(config.parent).CalcPoseInWorld(plant_context)
        start, end = frustum_segments(config)
        camera_path = f"{path}/{name}"
        meshcat.SetLineSegments(camera_path, start, end, 2.0, rgba)
        meshcat.SetTransform(camera_path, X_WP @ config.X_PC())
        paths.append(camera_path)
    return paths


class DetectionMarkers:
    """A sphere over every part a logical camera reports, updated at every
    runtime tick: ``runtime.on_tick(DetectionMarkers(...))``.

    The sphere floats just above the reported position (the part's centre plus
    half its size plus two radii, along world z): at the centre itself it would
    be hidden inside the part. Other models the cameras report (robots, grippers,
    bins) get no marker.

    Live, it moves the spheres in Meshcat. With ``visualizer`` (recording), it
    writes them into the visualizer's recording instead, so the replay shows them
    (each marker is a scene object with a transform and ``visible`` per frame).
    At most ``per_camera`` markers per camera.
    """

    def __init__(
        self,
        meshcat: Meshcat,
        station: Station,
        *,
        visualizer: Optional[MeshcatVisualizer] = None,
        path: str = "/detections",
        radius: float = 0.04,
        per_camera: int = 4,
        rgba: Rgba = MARKER_RGBA,
    ):
        if radius <= 0 or per_camera < 1:
            raise ConfigError(f"radius must be > 0 and per_camera >= 1, got {radius}, {per_camera}")
        self._meshcat = meshcat
        self._visualizer = visualizer
        self._slots: dict[str, list[str]] = {}
        for camera in sorted(station.cameras):
            self._slots[camera] = [f"{path}/{camera}/{k}" for k in range(per_camera)]
            for slot in self._slots[camera]:
                meshcat.SetObject(slot, Sphere(radius), rgba)
                meshcat.SetProperty(slot, "visible", False)
        self._shown: dict[str, bool] = {}
        #: camera name -> its sampling period (s): an older image is stale.
        self._period = {name: 1.0 / camera.config.update_rate_hz for name, camera in station.cameras.items()}
        #: part name -> height of its marker above the reported position (m).
        self._lift = {name: station.scenario.part_size(name) / 2 + 2 * radius for name in station.parts}

    def __call__(self, runtime: FactoryRuntime) -> None:
        animation = self._visualizer.get_mutable_recording() if self._visualizer is not None else None
        frame = animation.frame(runtime.time) if animation is not None else 0
        for camera, poses in self.marker_poses(runtime).items():
            slots = self._slots[camera]
            for k, slot in enumerate(slots):
                visible = k < len(poses)
                if animation is not None:
                    if visible:
                        animation.SetTransform(frame, slot, poses[k])
                    if self._shown.get(slot) != visible or frame == 0:
                        animation.SetProperty(frame, slot, "visible", visible)
                else:
                    if visible:
                        self._meshcat.SetTransform(slot, poses[k])
                    if self._shown.get(slot) != visible:
                        self._meshcat.SetProperty(slot, "visible", visible)
                self._shown[slot] = visible

    def marker_poses(self, runtime: FactoryRuntime) -> dict[str, list[RigidTransform]]:
        """Camera name -> world poses of its markers now (the parts it reports and
        does not see fully hidden, in its report's order, at most ``per_camera``)."""
        markers: dict[str, list[RigidTransform]] = {}
        for camera, slots in self._slots.items():
            image = runtime.camera_image(camera)
            if not runtime.time - image.time <= self._period[camera] + 1e-9:
                markers[camera] = []  # not sampled yet, or blacked out (its image is stale)
                continue
            markers[camera] = [
                RigidTransform((image.X_WC @ m.X_CM).translation() + [0.0, 0.0, self._lift[m.name]])
                for m in image.models
                if m.name in self._lift and m.visible_fraction > 0.0  # 0: reported, yet hidden
            ][: len(slots)]
        return markers


def add_visual_extras(runtime: FactoryRuntime, *, recording: bool = False) -> Optional[DetectionMarkers]:
    """Frusta and detection markers in the runtime's Meshcat (nothing without one).
    With ``recording``, the markers go into the visualizer's recording."""
    station = runtime.station
    if station.meshcat is None:
        return None
    draw_frusta(station.meshcat, station, runtime.context)
    markers = DetectionMarkers(station.meshcat, station, visualizer=station.visualizer if recording else None)
    runtime.on_tick(markers)
    return markers
