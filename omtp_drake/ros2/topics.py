"""The topics the cell publishes over ROS 2, in simulated time, and when.

============================================  =========================================  ==============
topic                                         type                                       when
============================================  =========================================  ==============
``/clock``                                    ``rosgraph_msgs/Clock``                    every step
``/joint_states``                             ``sensor_msgs/JointState``                 50 Hz
``/<ns>/joint_states`` (a model's plugin)     ``sensor_msgs/JointState``                 its rate
``/robot_description``                        ``std_msgs/String`` (transient local)      once, latched
``/<camera>/image_raw``                       ``sensor_msgs/Image`` (``rgb8``)           camera's rate
``/<camera>/camera_info``                     ``sensor_msgs/CameraInfo``                 camera's rate
``/<camera>/depth/image_raw``                 ``sensor_msgs/Image`` (``32FC1``, m)       camera's rate
``/<camera>/depth/camera_info``               ``sensor_msgs/CameraInfo``                 camera's rate
``/<camera>/points``                          ``sensor_msgs/PointCloud2``                camera's rate
``/omtp/<camera>/poses``                      ``geometry_msgs/PoseArray``                each image
``/omtp/<camera>/markers``                    ``visualization_msgs/MarkerArray``         each image
``/gripperN/attached``                        ``std_msgs/Bool``                          50 Hz
``/omtp/parts/poses``                         ``geometry_msgs/PoseArray``                10 Hz
``/omtp/parts/markers``                       ``visualization_msgs/MarkerArray``         10 Hz
============================================  =========================================  ==============

``<camera>`` topics exist for the logical cameras with an RGB-D view (``rgbd: true``
in the scenario), in the camera's optical frame ``<camera>_optical_frame``, the
names of Gazebo's depth camera plugin; they render only while someone subscribes
(the plugin is lazy too). The ``/omtp/<camera>`` topics exist for every logical
camera, in its frame ``<camera>_frame``, stamped with the image's time (Drake samples
at t when it steps on from t: the image goes out after the step that starts at t).
``/robot_description`` is published as robot_state_publisher does (reliable,
transient local, depth 1), so a late rviz2 or robot_state_publisher gets it. Every
topic is reliable: any subscriber's QoS matches.

``/omtp/parts`` are the parts in the world (ground truth, as Gazebo's model states;
they are no links of the URDF), in ``world``, in the order of the markers' names.

Joint names are the URDF's (``robot1_shoulder_pan_joint``...), so the user's own
robot_state_publisher turns ``/joint_states`` and ``/robot_description`` into tf.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from omtp_drake.cell.rgbd import camera_info, rgba_array
from omtp_drake.ros2 import messages

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: ``/joint_states`` and the grippers' state: the course's controllers' state rate.
JOINT_STATE_RATE_HZ = 50.0
#: ``/omtp/parts``: the logical cameras' default rate.
PARTS_RATE_HZ = 10.0
#: Seconds of ``/clock`` and ``/joint_states`` a reliable publisher keeps for a subscriber
#: that lags (KEEP_LAST: older ones are dropped). A subscriber process on a busy 2-core
#: machine stalled up to 0.2 s (bench_ros2.py); with 0.1 s queues it lost 7 % of /clock.
QUEUE_S = 1
#: Images and clouds kept for a lagging subscriber (0.5 s at 10 Hz; a cloud is 1 MB at 320 x 213).
IMAGE_QUEUE = 5


class Periodic:
    """Calls ``publish(t)`` when simulated time has reached its next due time
    (``period`` apart, from 0)."""

    def __init__(self, period: float, publish: Callable[[float], None]):
        self.period = period
        self._publish = publish
        self._next = 0.0

    def __call__(self, t: float) -> None:
        if t < self._next - 1e-9:
            return
        self._next = max(self._next + self.period, t)
        self._publish(t)


class ModelJointStates(Periodic):
    """``/<namespace>/joint_states`` of a model's ``libgazebo_ros_joint_state_publisher.so``
    (the tutorial robot's): its joints' positions and velocities at its ``update_rate``.
    (Until the one Gazebo layer of issue 44 serves the plugin to both transports.)"""

    def __init__(self, node: Any, cell: Cell, model: str, plugin: Any):
        from sensor_msgs.msg import JointState

        from omtp_drake.errors import ConfigError

        plant = cell.station.plant
        instance = cell.station.models[model]
        known = [plant.get_joint(j).name() for j in plant.GetJointIndices(instance)]
        missing = [j for j in plugin.joint_names if j not in known]
        if missing:
            raise ConfigError(
                f"joint state publisher of {model!r}: joint {missing[0]!r} does not exist; "
                f"valid: {', '.join(known)}"
            )
        self._cell = cell
        self._joints = [plant.GetJointByName(j, instance) for j in plugin.joint_names]
        name = "/" + "/".join(p for p in (*plugin.namespace.split("/"), "joint_states") if p)
        self._publisher = node.create_publisher(JointState, name, QUEUE_S * 50)
        super().__init__(1.0 / plugin.update_rate, self._publish_now)

    def _publish_now(self, t: float) -> None:
        context = self._cell.station.plant.GetMyContextFromRoot(self._cell.runtime.context)
        names = [j.name() for j in self._joints]
        message = messages.joint_state(t, names, [float(j.GetOnePosition(context)) for j in self._joints])
        message.velocity = [float(j.GetOneVelocity(context)) for j in self._joints]
        self._publisher.publish(message)


class CellTopics:
    """The publishers of the topics above on ``node`` (an rclpy node) for ``cell``."""

    def __init__(self, node: Any, cell: Cell, joints: list[tuple[str, str]], description: str):
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import JointState
        from std_msgs.msg import Bool, String

        self._node = node
        self._cell = cell
        self._joints = joints
        self._clock = node.create_publisher(Clock, "/clock", QUEUE_S * 100)
        self._joint_states = node.create_publisher(JointState, "/joint_states", QUEUE_S * 50)
        latched = QoSProfile(
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
        )
        self._description = node.create_publisher(String, "/robot_description", latched)
        self._description.publish(String(data=description))
        self._due: list[Callable[[float], None]] = []
        if joints:  # a cell without arms has no arms' joint states (no message without names)
            self._due.append(Periodic(1.0 / JOINT_STATE_RATE_HZ, self._publish_joint_states))
        for model in cell.scenario.models:
            for publisher in model.gazebo.joint_state_publishers:
                self._due.append(ModelJointStates(node, cell, model.name, publisher))
        self._grippers: dict[str, Any] = {}
        self._bool = Bool
        from omtp_drake.ros.gazebo.cell_services import gripper_plugins

        for robot, plugin in gripper_plugins(cell).items():
            self._grippers[robot] = node.create_publisher(Bool, f"/{plugin}/attached", 10)
        self._due.append(Periodic(1.0 / JOINT_STATE_RATE_HZ, self._publish_grippers))
        self._due.append(Periodic(1.0 / PARTS_RATE_HZ, PartsTopics(node, cell)))
        for config in cell.scenario.cameras:
            # Polled every step: each new image goes out at the first step after its sample.
            self._due.append(LogicalCameraTopics(node, cell, config.name))
            if config.rgbd:
                self._due.append(Periodic(1.0 / config.update_rate_hz, RgbdTopics(node, cell, config)))

    def publish(self, t: float) -> None:
        """``/clock`` first, then what is due at ``t``."""
        self._clock.publish(messages.clock(t))
        for due in self._due:
            due(t)

    def _publish_joint_states(self, t: float) -> None:
        names = [name for name, _ in self._joints]
        positions: list[float] = []
        for robot in dict.fromkeys(robot for _, robot in self._joints):
            positions += [float(q) for q in self._cell.arm(robot).joint_values()]
        self._joint_states.publish(messages.joint_state(t, names, positions))

    def _publish_grippers(self, t: float) -> None:
        for robot, publisher in self._grippers.items():
            publisher.publish(self._bool(data=self._cell.gripper(robot).attached))


class LogicalCameraTopics:
    """``/omtp/<camera>/poses`` and ``/markers``: each new image of the logical camera."""

    def __init__(self, node: Any, cell: Cell, camera: str):
        from geometry_msgs.msg import PoseArray
        from visualization_msgs.msg import MarkerArray

        self._cell = cell
        self._camera = cell.camera(camera)
        self._poses = node.create_publisher(PoseArray, f"/omtp/{camera}/poses", 10)
        self._markers = node.create_publisher(MarkerArray, f"/omtp/{camera}/markers", 10)
        self._last = -1.0

    def __call__(self, t: float) -> None:
        image = self._camera.image()
        if image.time <= self._last:
            return
        self._last = image.time
        self._poses.publish(messages.logical_pose_array(image))
        if self._markers.get_subscription_count() > 0:
            sizes = {name: self._cell.scenario.part_size(name) for name in self._cell.station.parts}
            self._markers.publish(messages.logical_markers(image, sizes))


class PartsTopics:
    """``/omtp/parts/poses`` and ``/markers``: every part in the world, in ``world``."""

    def __init__(self, node: Any, cell: Cell):
        from geometry_msgs.msg import PoseArray
        from visualization_msgs.msg import MarkerArray

        self._cell = cell
        self._poses = node.create_publisher(PoseArray, "/omtp/parts/poses", 10)
        self._markers = node.create_publisher(MarkerArray, "/omtp/parts/markers", 10)

    def __call__(self, t: float) -> None:
        cell = self._cell
        names = cell.runtime.parts_in_world()
        poses = [cell.part_pose(name) for name in names]
        self._poses.publish(messages.part_poses(t, poses))
        if self._markers.get_subscription_count() > 0:
            models = [(n, X, cell.scenario.part_size(n)) for n, X in zip(names, poses)]
            self._markers.publish(messages.model_markers(messages.header(t, "world"), "parts", models))


class RgbdTopics:
    """A camera's RGB-D view as Gazebo's depth camera plugin publishes it (rendered
    only while one of its topics has a subscriber)."""

    def __init__(self, node: Any, cell: Cell, config: Any):
        from sensor_msgs.msg import CameraInfo, Image, PointCloud2

        name = config.name
        self._cell = cell
        self._name = name
        self._frame = f"{name}_optical_frame"
        self._info = camera_info(config)
        self._image = node.create_publisher(Image, f"/{name}/image_raw", IMAGE_QUEUE)
        self._image_info = node.create_publisher(CameraInfo, f"/{name}/camera_info", IMAGE_QUEUE)
        self._depth = node.create_publisher(Image, f"/{name}/depth/image_raw", IMAGE_QUEUE)
        self._depth_info = node.create_publisher(CameraInfo, f"/{name}/depth/camera_info", IMAGE_QUEUE)
        self._points = node.create_publisher(PointCloud2, f"/{name}/points", IMAGE_QUEUE)
        self._all = (self._image, self._image_info, self._depth, self._depth_info, self._points)

    def __call__(self, t: float) -> None:
        if not any(p.get_subscription_count() > 0 for p in self._all):
            return
        diagram = self._cell.station.diagram
        context = diagram.GetMyContextFromRoot(self._cell.runtime.context)
        rgba = rgba_array(diagram.GetOutputPort(f"{self._name}.color_image").Eval(context))
        raw = diagram.GetOutputPort(f"{self._name}.depth_image").Eval(context)
        depth = messages.ros_depth(np.asarray(raw.data))
        info = messages.camera_info(t, self._frame, self._info)
        self._image.publish(messages.color_image(t, self._frame, rgba))
        self._image_info.publish(info)
        self._depth.publish(messages.depth_image(t, self._frame, depth))
        self._depth_info.publish(info)
        self._points.publish(messages.point_cloud(t, self._frame, depth, rgba, self._info))
