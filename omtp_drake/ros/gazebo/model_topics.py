"""The gazebo_ros plugins of a student's model on a run's graph, with the topics they give.

For each model of the scenario (a robot from ``--robot``, a launch file's spawn):

- ``libgazebo_ros_joint_state_publisher.so``: ``/<ns>/joint_states``
  (``sensor_msgs/JointState``: its joints' positions and velocities) at its
  ``update_rate``, stamped with the simulated time;
- ``libgazebo_ros_joint_pose_trajectory.so``: subscribes ``/<ns>/set_joint_trajectory``
  (``trajectory_msgs/JointTrajectory``); what it does with one is
  :mod:`omtp_drake.sim.joint_pose_trajectory`'s;
- ``libgazebo_ros_camera.so`` on a camera or depth sensor:
  ``/<ns>/<camera_name>/image_raw`` (``rgb8``) and ``camera_info``; a depth sensor adds
  ``depth/image_raw`` (``32FC1``, m; ``-inf`` nearer than ``min_depth``, ``+inf``
  beyond ``max_depth``), ``depth/camera_info`` and ``points`` (``PointCloud2``:
  ``x y z rgb`` float32 fields, 32 bytes a point, one per pixel, in ``frame_name``),
  one message each per new image (the sensor's rate, at most one per tick of the cell).

``camera_name`` defaults to the sensor's name and ``<ns>`` to ``/``: the tutorial's
depth camera ``my_camera`` publishes ``/my_camera/points``. The camera's ``K`` is
gazebo_ros's (principal point ((w + 1) / 2, (h + 1) / 2)). Unknown plugins are one
warning line each (:func:`unknown_plugins`).
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from omtp_drake.errors import ConfigError
from omtp_drake.ros.comm._core import JointPoseTrajectory, PosePoint
from omtp_drake.ros.comm.image_messages import CameraInfo, Image, PointCloud2, PointField
from omtp_drake.ros.comm.messages import Header, JointState, Message, Time
from omtp_drake.ros.gazebo.joint_state_topics import PeriodicSource
from omtp_drake.ros.gazebo.sensor_topics import Source

if TYPE_CHECKING:
    from omtp_drake.ros.comm._core import Cell, DepthCamera
    from omtp_drake.ros.gazebo.graph import Graph

_log = logging.getLogger("gazebo")


def topic(namespace: str, name: str) -> str:
    """``/<namespace>/<name>`` with one slash between parts."""
    return "/" + "/".join(p for p in (*namespace.split("/"), *name.split("/")) if p)


class PluginJointStates(PeriodicSource):
    """``joint_states`` of a joint state publisher plugin: its joints, at its rate."""

    msg_class = JointState

    def __init__(self, cell: Cell, model: str, joints: list[str], rate: float):
        super().__init__(cell, 1.0 / rate)
        station = cell.station
        instance = station.models[model]
        known = [station.plant.get_joint(j).name() for j in station.plant.GetJointIndices(instance)]
        missing = [j for j in joints if j not in known]
        if missing:
            raise ConfigError(
                f"joint state publisher of {model!r}: joint {missing[0]!r} does not exist; "
                f"valid: {', '.join(known)}"
            )
        self._joints = [station.plant.GetJointByName(j, instance) for j in joints]

    def message(self) -> Any:
        context = self._cell.station.plant.GetMyContextFromRoot(self._cell.runtime.context)
        return JointState(
            header=Header(stamp=Time(self._cell.time)),
            name=[j.name() for j in self._joints],
            position=[float(j.GetOnePosition(context)) for j in self._joints],
            velocity=[float(j.GetOneVelocity(context)) for j in self._joints],
        )


class CameraTopic(Source):
    """One topic of a camera plugin: a message per new image (``kind``: ``image``,
    ``info``, ``depth``, ``depth_info`` or ``points``)."""

    def __init__(self, cell: Cell, camera: DepthCamera, kind: str):
        self._cell = cell
        self._camera = camera
        self._kind = kind
        self._period = 1.0 / camera.config.rate
        self._last = -1
        self.msg_class = {"image": Image, "depth": Image, "points": PointCloud2}.get(kind, CameraInfo)
        plugin = camera.config.ros_camera
        self._frame = plugin.frame_name if plugin is not None else camera.config.link

    def poll(self) -> list[tuple[float, Any]]:
        index = math.floor(self._cell.time / self._period + 1e-6)
        if index <= self._last:
            return []
        self._last = index
        stamp = index * self._period
        header = Header(stamp=Time(stamp), frame_id=self._frame)
        return [(stamp, getattr(self, f"_{self._kind}")(header))]

    def _port(self, name: str) -> Any:
        station = self._cell.station
        context = station.diagram.GetMyContextFromRoot(self._cell.runtime.context)
        return station.diagram.GetOutputPort(f"{self._camera.config.name}.{name}").Eval(context)

    def _image(self, header: Message) -> Message:
        rgb = np.ascontiguousarray(np.asarray(self._port("color_image").data)[..., :3])
        h, w = rgb.shape[:2]
        return Image(header=header, height=h, width=w, encoding="rgb8", step=3 * w, data=rgb.tobytes())

    def _depth(self, header: Message) -> Message:
        depth = _gazebo_depths(np.asarray(self._port("depth_image").data)[..., 0])
        h, w = depth.shape
        return Image(header=header, height=h, width=w, encoding="32FC1", step=4 * w, data=depth.tobytes())

    def _info(self, header: Message) -> Message:
        info = self._camera.info
        w, h, f = info.width(), info.height(), info.focal_x()
        cx, cy = (w + 1) / 2.0, (h + 1) / 2.0
        return CameraInfo(
            header=header, height=h, width=w, distortion_model="plumb_bob", D=[0.0] * 5,
            K=[f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0], R=[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            P=[f, 0.0, cx, 0.0, 0.0, f, cy, 0.0, 0.0, 0.0, 1.0, 0.0],
        )  # fmt: skip

    _depth_info = _info

    def _points(self, header: Message) -> Message:
        depth = np.asarray(self._port("depth_image").data)[..., 0]
        xyz = np.array(self._port("point_cloud").xyzs().T, dtype=np.float32)  # (N, 3), pixel order
        rgb = np.asarray(self._port("color_image").data)[..., :3].reshape(-1, 3).astype(np.uint32)
        gazebo = _gazebo_depths(depth).reshape(-1)
        invalid = ~np.isfinite(gazebo)
        xyz[invalid] = gazebo[invalid, None]
        packed = np.zeros((xyz.shape[0], 8), dtype=np.float32)
        packed[:, :3] = xyz
        packed[:, 4] = ((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2]).view(np.float32)
        h, w = depth.shape
        fields = [PointField(name=n, offset=o, datatype=PointField.FLOAT32, count=1)
                  for n, o in (("x", 0), ("y", 4), ("z", 8), ("rgb", 16))]  # fmt: skip
        return PointCloud2(
            header=header, height=h, width=w, fields=fields, is_bigendian=False, point_step=32,
            row_step=32 * w, data=packed.tobytes(), is_dense=not invalid.any(),
        )  # fmt: skip


class Publishers(Source):
    """Two publishers of one topic: each one's messages, in the order they come."""

    def __init__(self, first: Source, second: Source):
        if first.msg_class is not second.msg_class:
            raise ConfigError(
                f"two publishers of one topic with types {first.msg_class._type} and {second.msg_class._type}"
            )
        self.msg_class = first.msg_class
        self.latch = first.latch or second.latch
        self._sources = (first, second)

    def poll(self) -> list[tuple[float, Any]]:
        return sorted(self._sources[0].poll() + self._sources[1].poll(), key=lambda pair: pair[0])


def _gazebo_depths(depth: np.ndarray) -> np.ndarray:
    """Drake's depths as gazebo_ros writes them: too close (0) is ``-inf``, too far ``+inf``."""
    out = np.array(depth, dtype=np.float32, copy=True)
    out[out <= 0.0] = -np.inf
    return out


def model_sources(cell: Cell) -> dict[str, Source]:
    """Topic name -> source of the models' joint state and camera plugins."""
    sources: dict[str, Source] = {}
    for model in cell.scenario.models:
        for publisher in model.gazebo.joint_state_publishers:
            name = topic(publisher.namespace, "joint_states")
            sources[name] = PluginJointStates(cell, model.name, publisher.joint_names, publisher.update_rate)
    for camera in cell.station.depth_cameras.values():
        plugin = camera.config.ros_camera
        if plugin is None:
            continue
        base = topic(plugin.namespace, plugin.camera_name)
        kinds = {"image_raw": "image", "camera_info": "info"}
        if camera.config.type == "depth":
            kinds |= {"depth/image_raw": "depth", "depth/camera_info": "depth_info", "points": "points"}
        for suffix, kind in kinds.items():
            sources[f"{base}/{suffix}"] = CameraTopic(cell, camera, kind)
    return sources


def attach_model_plugins(session: Graph) -> None:
    """The models' plugins on ``session``: their topics and the trajectory subscriptions. A
    topic the cell publishes already (the arms' ``/joint_states``) gets both publishers'
    messages, as two ROS publishers on one topic."""
    for name, source in model_sources(session.cell).items():
        existing = session.sources.get(name)
        session.sources[name] = source if existing is None else Publishers(existing, source)
    for edit in session.cell.runtime.driver.edits:
        if isinstance(edit, JointPoseTrajectory):
            session.subscribe(
                topic(edit.config.namespace, edit.config.topic), _on_trajectory(session, edit), (), 1
            )
    for line in unknown_plugins(session.cell):
        _log.warning(line)


def _on_trajectory(session: Graph, edit: JointPoseTrajectory):
    def callback(message: Any) -> None:
        points = [
            PosePoint(tuple(float(q) for q in p.positions), _seconds(p.time_from_start))
            for p in message.points
        ]
        try:
            edit.set_trajectory(
                list(message.joint_names), points, _seconds(message.header.stamp), session.cell.time
            )
        except ConfigError as e:
            _log.error("%s: %s. Trajectory not set.", edit.config.name, e)

    return callback


def _seconds(value: Any) -> float:
    return value.to_sec() if hasattr(value, "to_sec") else float(value)


def unknown_plugins(cell: Cell) -> list[str]:
    """One line per plugin of the models that the cell does not run."""
    lines = []
    for model in cell.scenario.models:
        for plugin in model.gazebo.unknown_plugins:
            where = f" on sensor link {plugin.link!r}" if plugin.link else ""
            lines.append(
                f"{model.file}: plugin {plugin.name!r} ({plugin.filename}){where} is not simulated; ignored"
            )
    return lines
