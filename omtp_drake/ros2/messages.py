"""The cell's state as ROS 2 messages (``rosgraph_msgs``, ``sensor_msgs``,
``geometry_msgs``, ``visualization_msgs``), as Gazebo's ROS 2 plugins fill them.

- Images (REP 118's encodings): colour ``rgb8``; depth ``32FC1`` in metres along
  the optical axis, REP 117's ``+inf`` beyond the camera's ``far`` and ``-inf``
  nearer than its ``near`` (Drake's depth image has ``inf`` and 0 there).
- ``camera_info``: the pinhole of :func:`omtp_drake.cell.rgbd.camera_info`, no
  distortion (``plumb_bob``, zeros), ``P = [K | 0]``.
- ``points``: an organized cloud (image height x width), fields ``x y z rgb``
  (float32; ``rgb`` packs 0x00RRGGBB in a float, PCL's layout), NaN where the depth
  has no return, in the optical frame, as the depth plugin publishes it.
- A logical camera's image: a ``geometry_msgs/PoseArray`` of the models' poses and
  a ``visualization_msgs/MarkerArray`` (a cube and a label per model) in the
  camera's frame, for rviz2 (the course's ``LogicalCameraImage`` type is no
  PyPI package).

This module imports the message packages: import it after
:func:`omtp_drake.ros2.network.import_rclpy`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, PoseArray, Quaternion, Vector3
from pydrake.math import RigidTransform
from pydrake.systems.sensors import CameraInfo as DrakeCameraInfo
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, JointState, PointCloud2, PointField
from std_msgs.msg import ColorRGBA, Header
from visualization_msgs.msg import Marker, MarkerArray

from omtp_drake.cell.camera_image import LogicalCameraImage

#: The cube drawn for a model a logical camera reports (m); parts get their own size.
MARKER_SIZE = 0.05


def stamp(t: float) -> Time:
    """Simulated time ``t`` (s) as a ROS 2 time."""
    ns = int(round(t * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def header(t: float, frame_id: str = "") -> Header:
    return Header(stamp=stamp(t), frame_id=frame_id)


def clock(t: float) -> Clock:
    return Clock(clock=stamp(t))


def joint_state(t: float, names: Sequence[str], positions: Sequence[float]) -> JointState:
    return JointState(header=header(t), name=list(names), position=[float(q) for q in positions])


def color_image(t: float, frame_id: str, rgba: np.ndarray) -> Image:
    """An ``rgb8`` image from a (height, width, 4) uint8 array."""
    height, width = rgba.shape[:2]
    rgb = np.ascontiguousarray(rgba[:, :, :3])
    return Image(
        header=header(t, frame_id),
        height=height,
        width=width,
        encoding="rgb8",
        is_bigendian=0,
        step=width * 3,
        data=rgb.tobytes(),
    )


def ros_depth(depth: np.ndarray) -> np.ndarray:
    """Drake's depth (m; ``inf`` too far, 0 too near) in REP 117's convention (float32)."""
    out = np.array(depth, dtype=np.float32, copy=True).reshape(depth.shape[0], depth.shape[1])
    out[out == 0.0] = -np.inf
    return out


def depth_image(t: float, frame_id: str, depth_m: np.ndarray) -> Image:
    """A ``32FC1`` image from a (height, width) float32 array in REP 117's convention."""
    height, width = depth_m.shape
    return Image(
        header=header(t, frame_id),
        height=height,
        width=width,
        encoding="32FC1",
        is_bigendian=0,
        step=width * 4,
        data=np.ascontiguousarray(depth_m, dtype="<f4").tobytes(),
    )


def camera_info(t: float, frame_id: str, info: DrakeCameraInfo) -> CameraInfo:
    fx, fy, cx, cy = info.focal_x(), info.focal_y(), info.center_x(), info.center_y()
    return CameraInfo(
        header=header(t, frame_id),
        height=info.height(),
        width=info.width(),
        distortion_model="plumb_bob",
        d=[0.0] * 5,
        k=[fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0],
        r=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        p=[fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
    )


_CLOUD_DTYPE = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")])
_CLOUD_FIELDS = [
    PointField(name=name, offset=4 * i, datatype=PointField.FLOAT32, count=1)
    for i, name in enumerate(("x", "y", "z", "rgb"))
]


def cloud_points(depth_m: np.ndarray, info: DrakeCameraInfo) -> np.ndarray:
    """(height, width, 3) float32 points in the optical frame from a REP 117 depth
    image (NaN where it has no finite depth)."""
    height, width = depth_m.shape
    v, u = np.mgrid[0:height, 0:width].astype(np.float32)
    z = np.where(np.isfinite(depth_m), depth_m, np.nan).astype(np.float32)
    x = (u - info.center_x()) * z / info.focal_x()
    y = (v - info.center_y()) * z / info.focal_y()
    return np.stack([x, y, z], axis=-1)


def point_cloud(
    t: float, frame_id: str, depth_m: np.ndarray, rgba: np.ndarray, info: DrakeCameraInfo
) -> PointCloud2:
    """The organized cloud of a depth image, coloured by the colour image of the same view."""
    height, width = depth_m.shape
    xyz = cloud_points(depth_m, info)
    packed = np.zeros((height, width), dtype=_CLOUD_DTYPE)
    packed["x"], packed["y"], packed["z"] = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    rgb = rgba[:, :, :3].astype(np.uint32)
    packed["rgb"] = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    return PointCloud2(
        header=header(t, frame_id),
        height=height,
        width=width,
        fields=_CLOUD_FIELDS,
        is_bigendian=False,
        point_step=_CLOUD_DTYPE.itemsize,
        row_step=_CLOUD_DTYPE.itemsize * width,
        data=packed.tobytes(),
        is_dense=False,
    )


def pose(X: RigidTransform) -> Pose:
    q = X.rotation().ToQuaternion()
    p = X.translation()
    return Pose(
        position=Point(x=float(p[0]), y=float(p[1]), z=float(p[2])),
        orientation=Quaternion(x=q.x(), y=q.y(), z=q.z(), w=q.w()),
    )


def logical_pose_array(image: LogicalCameraImage) -> PoseArray:
    """Every model the image reports, its origin's pose in the camera frame."""
    return PoseArray(header=header(image.time, image.frame), poses=[pose(m.X_CM) for m in image.models])


def logical_markers(image: LogicalCameraImage, part_sizes: dict[str, float]) -> MarkerArray:
    """rviz2's view of a logical camera image (see :func:`model_markers`): parts green
    at their size, other models grey at :data:`MARKER_SIZE`."""
    models = [(m.name or m.type, m.X_CM, part_sizes.get(m.name)) for m in image.models]
    return model_markers(header(image.time, image.frame), image.camera_name, models)


def model_markers(
    h: Header, ns: str, models: Sequence[tuple[str, RigidTransform, float | None]]
) -> MarkerArray:
    """First a DELETEALL (what is gone goes), then per (name, pose, part size or None)
    a cube at the pose (a part: its size, green; else :data:`MARKER_SIZE`, grey) and
    its name above it."""
    markers = [Marker(header=h, ns=ns, action=Marker.DELETEALL)]
    for i, (name, X, part_size) in enumerate(models):
        size = part_size if part_size is not None else MARKER_SIZE
        color = (
            ColorRGBA(r=0.1, g=0.8, b=0.2, a=0.8)
            if part_size is not None
            else ColorRGBA(r=0.6, g=0.6, b=0.6, a=0.5)
        )
        cube = Marker(header=h, ns=ns, id=2 * i, type=Marker.CUBE, action=Marker.ADD, pose=pose(X))
        cube.scale, cube.color = Vector3(x=size, y=size, z=size), color
        label = Marker(header=h, ns=ns, id=2 * i + 1, type=Marker.TEXT_VIEW_FACING, action=Marker.ADD)
        label.pose = pose(X)
        label.pose.position.z += size / 2 + 0.03
        label.scale, label.color, label.text = Vector3(z=0.04), ColorRGBA(r=1.0, g=1.0, b=1.0, a=1.0), name
        markers += [cube, label]
    return MarkerArray(markers=markers)


def part_poses(t: float, poses: Sequence[RigidTransform]) -> PoseArray:
    """Parts' poses in the world frame."""
    return PoseArray(header=header(t, "world"), poses=[pose(X) for X in poses])
