"""The cell's state as ROS 2 messages (``rosgraph_msgs``, ``sensor_msgs``,
``geometry_msgs``, ``visualization_msgs``), as Gazebo's ROS 2 plugins fill them.

- The Gazebo plugin layer's messages (:mod:`omtp_drake.gazebo.messages`) field for
  field (:func:`to_ros`), and a ``JointTrajectory`` as its request; the plugins'
  rules (encodings, frames, intrinsics) are theirs, not this module's.
- A logical camera's image: a ``geometry_msgs/PoseArray`` of the models' poses and
  a ``visualization_msgs/MarkerArray`` (a cube and a label per model) in the
  camera's frame, for rviz2 (the course's ``LogicalCameraImage`` type is no
  PyPI package).

This module imports the message packages: import it after
:func:`omtp_drake.ros2.network.import_rclpy`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, PoseArray, Quaternion, Vector3
from pydrake.math import RigidTransform
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, JointState, PointCloud2, PointField
from std_msgs.msg import ColorRGBA, Header
from visualization_msgs.msg import Marker, MarkerArray

from omtp_drake.cell.camera_image import LogicalCameraImage
from omtp_drake.gazebo import messages as neutral
from omtp_drake.sim import trajectory_request as request

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


#: Neutral message type -> the ROS 2 type it is published as.
TYPES: dict[type, type] = {
    neutral.JointStates: JointState,
    neutral.Image: Image,
    neutral.CameraInfo: CameraInfo,
    neutral.PointCloud: PointCloud2,
}


def to_ros(m: Any) -> Any:
    """A published message of the plugin layer as its ROS 2 message, field for field."""
    fields = neutral.message_fields(m)
    if "fields" in fields:
        fields["fields"] = [
            PointField(name=n, offset=o, datatype=PointField.FLOAT32, count=1) for n, o in fields["fields"]
        ]
    return TYPES[type(m)](header=header(m.stamp, m.frame_id), **fields)


def seconds(t: Any) -> float:
    """A ``builtin_interfaces`` Time or Duration in seconds."""
    return t.sec + t.nanosec * 1e-9


def trajectory_request(msg: Any) -> request.TrajectoryRequest:
    """A ``trajectory_msgs/msg/JointTrajectory`` as the request every plugin and controller reads."""
    return request.trajectory_request(msg, seconds)


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


def part_poses(t: float, frame_id: str, poses: Sequence[RigidTransform]) -> PoseArray:
    """Parts' poses in ``frame_id``."""
    return PoseArray(header=header(t, frame_id), poses=[pose(X) for X in poses])
