"""``gazebo_ros_camera``: a camera or depth sensor's images, camera info and points.

Which cameras: every ``camera``/``depth`` sensor of a model whose ``<sensor>`` carries
``libgazebo_ros_camera.so``, and every logical camera with an RGB-D view (``rgbd: true``
in the scenario), published as if that plugin sat on it (frame
``<camera>_optical_frame``, namespace ``/``, camera name the camera's).

Topics under ``<ns>/<camera_name>`` (``camera_name`` defaults to the sensor's name):
``image_raw`` (``rgb8``) and ``camera_info``; a depth view adds ``depth/image_raw``
(``32FC1``, m), ``depth/camera_info`` and ``points``. One message each per new sample
of the sensor, at its rate, stamped with the sample's time, in the plugin's
``frame_name`` (else the sensor's link). Lazy: rendered only while subscribed.

The rules, as the plugin (gazebo_ros_pkgs ``ros2`` and ``noetic-devel`` agree):

- ``camera_info``: ``K``'s principal point is the plugin's default ``((w + 1) / 2,
  (h + 1) / 2)`` (its ``<cx>``/``<cy>`` are not read here), focal length ``f`` on both
  axes, ``plumb_bob`` with zero distortion, ``P = [K | 0]``.
- depth: within (``min_depth``, ``max_depth``) the depth along the optical axis;
  nearer ``-inf``, farther ``+inf`` (REP 117). Drake's renderer is set to that range
  (:mod:`omtp_drake.cell.depth_camera`) and returns 0 and ``inf`` outside it.
- ``points``: one point per pixel, row by row (organized, height x width), fields
  ``x y z`` at offsets 0, 4, 8 and ``rgb`` at 16 (float32 each), 32 bytes a point, as
  ``setPointCloud2FieldsByString(2, "xyz", "rgb")`` lays them out; a pixel's point is its
  ray through the image centre ``((w - 1) / 2, (h - 1) / 2)`` (the plugin's ray angles;
  Drake's pinhole centre is the same) scaled to its depth; out of range all three
  coordinates are that depth's ``-inf`` or ``+inf`` and ``is_dense`` is false. ``rgb``
  packs the colour PCL's way (``0x00RRGGBB`` as the float's bits).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from pydrake.systems.sensors import CameraInfo as DrakeCameraInfo

from omtp_drake.cell.rgbd import camera_info as logical_camera_info
from omtp_drake.gazebo.messages import CameraInfo, CloudField, Image, PointCloud
from omtp_drake.gazebo.schedule import Publication, Sampled, topic

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: REP 118's encodings of the plugin's images.
COLOR_ENCODING = "rgb8"
DEPTH_ENCODING = "32FC1"
#: A logical camera's optical frame, as its RGB-D view is published.
OPTICAL_FRAME = "{camera}_optical_frame"
#: The cloud's fields (name, byte offset; FLOAT32 each) and bytes per point.
CLOUD_FIELDS = (CloudField("x", 0), CloudField("y", 4), CloudField("z", 8), CloudField("rgb", 16))
POINT_STEP = 32


@dataclass(frozen=True)
class CameraView:
    """One camera as the plugin publishes it: ``ports`` is the diagram's port prefix
    (``<ports>.color_image``, ``<ports>.depth_image``)."""

    ports: str
    base: str
    frame: str
    rate: float
    info: DrakeCameraInfo
    depth: bool
    plugin: str


def camera_views(cell: Cell) -> list[CameraView]:
    """Every camera of ``cell`` with the plugin (or a logical camera's RGB-D view)."""
    views = []
    for camera in cell.station.depth_cameras.values():
        config, plugin = camera.config, camera.config.ros_camera
        if plugin is None:
            continue
        base = topic(plugin.namespace, plugin.camera_name or config.name)
        frame = plugin.frame_name or config.link
        views.append(
            CameraView(
                config.name, base, frame, config.rate, camera.info, config.type == "depth", plugin.name
            )
        )
    for logical in cell.scenario.cameras:
        if logical.rgbd:
            name = logical.name
            frame = OPTICAL_FRAME.format(camera=name)
            info = logical_camera_info(logical)
            views.append(CameraView(name, f"/{name}", frame, logical.update_rate_hz, info, True, name))
    return views


def camera_publications(cell: Cell, view: CameraView) -> list[Publication]:
    """The topics of ``view`` (see the module doc)."""
    frames = CameraFrames(cell, view)
    kinds: dict[str, tuple[type, Any]] = {
        "image_raw": (Image, frames.image),
        "camera_info": (CameraInfo, frames.info),
    }
    if view.depth:
        kinds |= {
            "depth/image_raw": (Image, frames.depth),
            "depth/camera_info": (CameraInfo, frames.info),
            "points": (PointCloud, frames.points),
        }
    return [
        Publication(f"{view.base}/{suffix}", message, Sampled(view.rate, make), lazy=True, plugin=view.plugin)
        for suffix, (message, make) in kinds.items()
    ]


class CameraFrames:
    """The messages of one camera at a stamp, from the diagram's ports now."""

    def __init__(self, cell: Cell, view: CameraView):
        self._cell = cell
        self._view = view
        diagram = cell.station.diagram
        self._color = diagram.GetOutputPort(f"{view.ports}.color_image")
        self._depth = diagram.GetOutputPort(f"{view.ports}.depth_image") if view.depth else None

    def _eval(self, port: Any) -> np.ndarray:
        diagram = self._cell.station.diagram
        return np.asarray(port.Eval(diagram.GetMyContextFromRoot(self._cell.runtime.context)).data)

    def rgb(self) -> np.ndarray:
        return np.ascontiguousarray(self._eval(self._color)[..., :3])

    def depths(self) -> np.ndarray:
        """REP 117 depths (float32, height x width)."""
        return gazebo_depths(self._eval(self._depth)[..., 0])

    def image(self, stamp: float) -> Image:
        rgb = self.rgb()
        h, w = rgb.shape[:2]
        return Image(stamp, self._view.frame, h, w, COLOR_ENCODING, 3 * w, rgb.tobytes())

    def depth(self, stamp: float) -> Image:
        depth = self.depths()
        h, w = depth.shape
        return Image(stamp, self._view.frame, h, w, DEPTH_ENCODING, 4 * w, depth.astype("<f4").tobytes())

    def info(self, stamp: float) -> CameraInfo:
        return camera_info(stamp, self._view.frame, self._view.info)

    def points(self, stamp: float) -> PointCloud:
        return point_cloud(stamp, self._view.frame, self.depths(), self.rgb(), self._view.info)


def gazebo_depths(depth: np.ndarray) -> np.ndarray:
    """Drake's depths (0 too near, ``inf`` too far) as the plugin writes them (REP 117)."""
    out = np.array(depth, dtype=np.float32, copy=True)
    out[out <= 0.0] = -np.inf
    return out


def camera_info(stamp: float, frame_id: str, info: DrakeCameraInfo) -> CameraInfo:
    """The plugin's camera info of ``info``'s image size and focal lengths."""
    w, h, fx, fy = info.width(), info.height(), info.focal_x(), info.focal_y()
    cx, cy = (w + 1) / 2.0, (h + 1) / 2.0
    return CameraInfo(
        stamp, frame_id, h, w, "plumb_bob", (0.0,) * 5,
        (fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        (fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0),
    )  # fmt: skip


@functools.lru_cache(maxsize=8)
def _rays(w: int, h: int, fx: float, fy: float, cx: float, cy: float) -> tuple[np.ndarray, np.ndarray]:
    """Each pixel's ray as (x / z, y / z): one row of x factors, one column of y factors."""
    rx = ((np.arange(w) - cx) / fx).astype(np.float32)[None, :]
    ry = ((np.arange(h) - cy) / fy).astype(np.float32)[:, None]
    return rx, ry


def cloud_xyz(depth: np.ndarray, info: DrakeCameraInfo, out: np.ndarray | None = None) -> np.ndarray:
    """(height, width, 3) float32 points of REP 117 ``depth`` (out of range: its ±inf),
    written into ``out`` (a (height, width, >= 3) float32 array) when given."""
    h, w = depth.shape
    xyz = np.empty((h, w, 3), dtype=np.float32) if out is None else out
    rx, ry = _rays(w, h, info.focal_x(), info.focal_y(), info.center_x(), info.center_y())
    np.multiply(depth, rx, out=xyz[..., 0])
    np.multiply(depth, ry, out=xyz[..., 1])
    xyz[..., 2] = depth
    invalid = ~np.isfinite(depth)
    if invalid.any():
        xyz[invalid, :3] = depth[invalid, None]
    return xyz


def point_cloud(
    stamp: float, frame_id: str, depth: np.ndarray, rgb: np.ndarray, info: DrakeCameraInfo
) -> PointCloud:
    """The plugin's organized cloud of ``depth`` coloured by ``rgb`` (see the module doc)."""
    h, w = depth.shape
    packed = np.zeros((h, w, POINT_STEP // 4), dtype=np.float32)
    cloud_xyz(depth, info, out=packed)
    c = rgb.astype(np.uint32)
    packed[..., 4] = ((c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]).view(np.float32)
    dense = bool(np.isfinite(depth).all())
    return PointCloud(
        stamp, frame_id, h, w, CLOUD_FIELDS, POINT_STEP, POINT_STEP * w, packed.tobytes(), dense
    )
