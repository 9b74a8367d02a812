"""The topics the cell publishes over ROS 2, in simulated time, and when.

The Gazebo plugins' topics are :func:`omtp_drake.gazebo.plugins.gazebo_plugins`'s: the
rules (rates, frames, stamps, encodings) are the plugin layer's, the same as under
``ros-run``; here each gets its ROS 2 type (``sensor_msgs/JointState``, ``Image``,
``CameraInfo``, ``PointCloud2``) and a queue depth (:data:`QUEUE_DEPTH`). Every message
of a volatile topic here goes out only while someone would get it
(:func:`~omtp_drake.ros2.audience.heard`: a subscriber, or the bag); the plugins' schedules run
regardless, but a lazy publication (the cameras) is not even polled meanwhile.

============================================  =========================================  ==============
topic                                         type                                       when
============================================  =========================================  ==============
``/clock``                                    ``rosgraph_msgs/Clock``                    every step
the plugins' topics                           (above)                                    theirs
``/robot_description``                        ``std_msgs/String`` (transient local)      once, latched
``/omtp/<camera>/poses``                      ``geometry_msgs/PoseArray``                each image
``/omtp/<camera>/markers``                    ``visualization_msgs/MarkerArray``         each image
``/omtp/logical_camera/poses``, ``/markers``  the single camera's, the same              each image
``/omtp/parts/poses``                         ``geometry_msgs/PoseArray``                the parts' rate
``/omtp/parts/markers``                       ``visualization_msgs/MarkerArray``         the parts' rate
============================================  =========================================  ==============

The plugins' topics of the course's own types (the grippers' state, the break beam) are
:mod:`omtp_drake.ros2.course_topics`'.

The ``/omtp/<camera>`` topics are the logical camera plugin's
(:mod:`omtp_drake.gazebo.logical_camera`: every Gazebo model in view, as the course's
plugin lists them), in the camera's frame ``<camera>_frame``, stamped with the image's
time (Drake samples at t when it steps on from t: the image goes out after the step
that starts at t). ``/robot_description`` is
published as robot_state_publisher does (reliable, transient local, depth 1), so a late
rviz2 or robot_state_publisher gets it. Every topic is reliable: any subscriber's QoS
matches.

``/omtp/parts`` are :mod:`omtp_drake.gazebo.parts`: the parts in the world (ground
truth, as Gazebo's model states; they are no links of the URDF), in the order of the
markers' names.

Joint names are the URDF's (``robot1_shoulder_pan_joint``...), so the user's own
robot_state_publisher turns ``/joint_states`` and ``/robot_description`` into tf.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from omtp_drake.gazebo.plugins import GazeboPlugins
from omtp_drake.gazebo.schedule import Publication
from omtp_drake.ros2 import messages
from omtp_drake.ros2.audience import heard

if TYPE_CHECKING:
    from omtp_drake.script import Cell

#: Seconds of ``/clock`` a reliable publisher keeps for a subscriber that lags (KEEP_LAST:
#: older ones are dropped). A subscriber process on a busy 2-core machine stalled up to
#: 0.2 s (bench_ros2.py); with 0.1 s queues it lost 7 % of /clock.
QUEUE_S = 1
#: Messages kept for a lagging subscriber: joint states (1 s at 50 Hz), images and
#: clouds (0.5 s at 10 Hz; a cloud is 1 MB at 320 x 213).
QUEUE_DEPTH = {"JointStates": 50, "Image": 5, "CameraInfo": 5, "PointCloud": 5}


class PluginPublisher:
    """A publication of the plugin layer as an rclpy publisher: polled at every step (a lazy one
    only while heard), its messages converted and sent only while heard (latched ones always)."""

    def __init__(self, node: Any, publication: Publication):
        msg_type = messages.TYPES[publication.message]
        depth = QUEUE_DEPTH.get(publication.message.__name__, 10)
        self._publisher = node.create_publisher(msg_type, publication.topic, depth)
        self._poll = publication.poll
        self._lazy = publication.lazy
        self._latched = publication.latched

    def __call__(self, t: float) -> None:
        if self._lazy and not heard(self._publisher):
            return
        for message in self._poll(t):  # mostly none: asked only when one is due
            if self._latched or heard(self._publisher):
                self._publisher.publish(messages.to_ros(message))


class CellTopics:
    """The publishers of the topics above on ``node`` (an rclpy node) for ``cell``,
    whose Gazebo plugins are ``plugins``."""

    def __init__(self, node: Any, cell: Cell, plugins: GazeboPlugins, description: str):
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        from rosgraph_msgs.msg import Clock
        from std_msgs.msg import String

        from omtp_drake.gazebo.logical_camera import camera_views, logical_camera_publications
        from omtp_drake.gazebo.parts import parts_publication

        self._cell = cell
        self._clock = node.create_publisher(Clock, "/clock", QUEUE_S * 100)
        latched = QoSProfile(
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE
        )
        self._description = node.create_publisher(String, "/robot_description", latched)
        self._description.publish(String(data=description))
        self._due: list[Any] = [
            PluginPublisher(node, p) for p in plugins.publications if p.message in messages.TYPES
        ]
        self._due.append(PartsTopics(node, parts_publication(cell)))
        # Polled every step: each new image goes out at the first step after its sample.
        views = camera_views(cell)
        self._due += [LogicalCameraTopics(node, cell, p) for p in logical_camera_publications(cell, views)]
        # tf's detected frames are the plugin's, as on ROS 1 (its listing: names and prefix).
        cell.tf.use_images(lambda camera: views[camera].image_of)

    def publish(self, t: float) -> None:
        """``/clock`` first, then what is due at ``t``."""
        if heard(self._clock):
            self._clock.publish(messages.clock(t))
        for due in self._due:
            due(t)


class LogicalCameraTopics:
    """A logical camera plugin's topic ``/omtp/<camera>`` as ``/omtp/<camera>/poses`` and
    ``/markers`` (each while heard): the course's ``LogicalCameraImage`` type is no PyPI package."""

    def __init__(self, node: Any, cell: Cell, publication: Publication):
        from geometry_msgs.msg import PoseArray
        from visualization_msgs.msg import MarkerArray

        self._cell = cell
        self._poll = publication.poll
        self._poses = node.create_publisher(PoseArray, f"{publication.topic}/poses", 10)
        self._markers = node.create_publisher(MarkerArray, f"{publication.topic}/markers", 10)

    def __call__(self, t: float) -> None:
        for image in self._poll(t):
            if heard(self._poses):
                self._poses.publish(messages.logical_pose_array(image))
            if heard(self._markers):
                sizes = {name: self._cell.scenario.part_size(name) for name in self._cell.station.parts}
                self._markers.publish(messages.logical_markers(image, sizes))


class PartsTopics:
    """``/omtp/parts/poses`` and ``/markers``: :mod:`omtp_drake.gazebo.parts` as a
    ``PoseArray`` and rviz2's markers (each while heard)."""

    def __init__(self, node: Any, publication: Publication):
        from geometry_msgs.msg import PoseArray
        from visualization_msgs.msg import MarkerArray

        self._poll = publication.poll
        self._poses = node.create_publisher(PoseArray, f"{publication.topic}/poses", 10)
        self._markers = node.create_publisher(MarkerArray, f"{publication.topic}/markers", 10)

    def __call__(self, t: float) -> None:
        for m in self._poll(t):
            if heard(self._poses):
                self._poses.publish(messages.part_poses(m.stamp, m.frame_id, m.poses))
            if heard(self._markers):
                models = list(zip(m.names, m.poses, m.sizes))
                self._markers.publish(
                    messages.model_markers(messages.header(m.stamp, m.frame_id), "parts", models)
                )
