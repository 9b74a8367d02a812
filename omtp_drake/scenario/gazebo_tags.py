"""A URDF's ``<gazebo>`` extension tags as typed settings (part of the scenario YAML schema).

A robot's description says what Gazebo adds to it in ``<gazebo>`` elements: per link
(``reference="LINK"``) a material, friction (``mu1``, ``mu2``) and sensors; for the
model, plugins. :mod:`omtp_drake.scenario.gazebo_parse` reads them into these
dataclasses; each checks its own values in ``validate(where)`` (``where``: the file,
named in the error), once, apart from what applies them: the cell's models
(:mod:`omtp_drake.cell.described_models`), its depth cameras
(:mod:`omtp_drake.cell.depth_camera`) and the ROS topics of the plugins.

The plugins known here are the ones the URDF tutorial's robot uses, with gazebo_ros's
parameters and defaults (ROS 2's names; ROS 1's spellings are read too):

- ``libgazebo_ros_camera.so`` on a ``camera`` or ``depth`` sensor: :class:`RosCameraPlugin`;
- ``libgazebo_ros_joint_state_publisher.so``: :class:`JointStatePublisherPlugin`;
- ``libgazebo_ros_joint_pose_trajectory.so``: :class:`JointPoseTrajectoryPlugin`.

Any other plugin is kept as a :class:`PluginConfig` (name and file): the cell warns once
for each and does nothing else with it.
"""

import math
from dataclasses import dataclass, field
from typing import Optional

from omtp_drake.errors import MAX_RATE_HZ, ConfigError
from omtp_drake.scenario.ros_control import RosControlConfig

#: The sensor types whose images the cell renders.
CAMERA_SENSOR_TYPES = ("camera", "depth")
#: The noise models a camera's ``<noise>`` may name (Gazebo's image noise).
NOISE_TYPES = ("none", "gaussian")
#: The image formats the cell renders: 8-bit colour (Gazebo's names).
IMAGE_FORMATS = ("R8G8B8", "B8G8R8", "R8B8G8", "RGB_INT8", "L8")
#: The largest image side the cell renders (pixels).
MAX_IMAGE_SIDE = 4096


def _check_rate(what: str, value: float, *, zero_ok: bool) -> None:
    low_ok = value >= 0 if zero_ok else value > 0
    if not (low_ok and value <= MAX_RATE_HZ):
        bound = "[0" if zero_ok else "(0"
        raise ConfigError(f"{what} must be in {bound}, {MAX_RATE_HZ:g}] Hz, got {value}")


@dataclass
class GazeboMaterial:
    """``<gazebo reference="LINK"><material>Gazebo/Orange</material>``."""

    link: str = ""
    name: str = ""


@dataclass
class LinkFriction:
    """``<gazebo reference="LINK"><mu1>..</mu1><mu2>..</mu2>`` (Coulomb friction)."""

    link: str = ""
    mu1: float = 1.0
    mu2: float = 1.0

    def validate(self, where: str) -> None:
        for key in ("mu1", "mu2"):
            value = getattr(self, key)
            if not (value >= 0 and math.isfinite(value)):
                raise ConfigError(
                    f"{where}: <gazebo reference={self.link!r}> {key} must be a finite number >= 0, "
                    f"got {value}"
                )


@dataclass
class CameraSettings:
    """A sensor's ``<camera>``: the image, the clip planes and the image noise."""

    horizontal_fov: float = 1.047
    width: int = 320
    height: int = 240
    format: str = "R8G8B8"
    near: float = 0.1
    far: float = 100.0
    noise_type: str = "none"
    noise_mean: float = 0.0
    noise_stddev: float = 0.0

    def validate(self, where: str) -> None:
        if not 0 < self.horizontal_fov < math.pi:
            raise ConfigError(f"{where}: horizontal_fov must be in (0, pi) rad, got {self.horizontal_fov}")
        for key in ("width", "height"):
            value = getattr(self, key)
            if not 1 <= value <= MAX_IMAGE_SIDE:
                raise ConfigError(f"{where}: image {key} must be in [1, {MAX_IMAGE_SIDE}], got {value}")
        if self.format not in IMAGE_FORMATS:
            raise ConfigError(f"{where}: image format {self.format!r}; valid: {', '.join(IMAGE_FORMATS)}")
        if not (0 < self.near < self.far and math.isfinite(self.far)):
            raise ConfigError(f"{where}: clip needs 0 < near < far, got near={self.near}, far={self.far}")
        if self.noise_type not in NOISE_TYPES:
            raise ConfigError(f"{where}: noise type {self.noise_type!r}; valid: {', '.join(NOISE_TYPES)}")
        if not (self.noise_stddev >= 0 and math.isfinite(self.noise_stddev)):
            raise ConfigError(f"{where}: noise stddev must be a finite number >= 0, got {self.noise_stddev}")


@dataclass
class RosCameraPlugin:
    """``libgazebo_ros_camera.so`` on a camera or depth sensor (gazebo_ros's names and defaults).

    Topics (``/<namespace>/<camera_name>/...``): ``image_raw``, ``camera_info``; a depth
    sensor adds ``depth/image_raw``, ``depth/camera_info`` and ``points``."""

    name: str = ""
    #: ``<camera_name>`` (default: the sensor's name).
    camera_name: str = ""
    namespace: str = "/"
    #: ``<frame_name>``: the frame of the images and points (default: the sensor's link).
    frame_name: str = ""
    #: Depths outside (min_depth, max_depth) are no points (-inf nearer, +inf farther);
    #: ``max_depth`` None: no limit (gazebo_ros's infinity).
    min_depth: float = 0.4
    max_depth: Optional[float] = None
    #: ``<update_rate>`` of the plugin (0: the sensor's).
    update_rate: float = 0.0

    def validate(self, where: str) -> None:
        _check_rate(f"{where}: plugin {self.name!r} update_rate", self.update_rate, zero_ok=True)
        far = math.inf if self.max_depth is None else self.max_depth
        if not (0 <= self.min_depth < far):
            raise ConfigError(
                f"{where}: plugin {self.name!r} needs 0 <= min_depth < max_depth, "
                f"got min_depth={self.min_depth}, max_depth={self.max_depth}"
            )


@dataclass
class SensorConfig:
    """A ``<sensor>`` in ``<gazebo reference="LINK">`` and the plugin that publishes it."""

    name: str = ""
    type: str = "camera"
    link: str = ""
    #: The sensor's pose in its link: ``<pose>x y z roll pitch yaw</pose>``.
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    update_rate: float = 0.0
    always_on: bool = False
    visualize: bool = False
    camera: Optional[CameraSettings] = None
    #: Its ``libgazebo_ros_camera.so`` (None: the sensor publishes nothing to ROS).
    ros_camera: Optional[RosCameraPlugin] = None

    @property
    def is_camera(self) -> bool:
        return self.type in CAMERA_SENSOR_TYPES

    @property
    def rate(self) -> float:
        """Images per second: the plugin's rate, else the sensor's."""
        if self.ros_camera is not None and self.ros_camera.update_rate > 0:
            return self.ros_camera.update_rate
        return self.update_rate

    def validate(self, where: str) -> None:
        here = f"{where}: sensor {self.name!r} on {self.link!r}"
        if not self.name:
            raise ConfigError(f"{where}: a <sensor> on {self.link!r} has no name")
        _check_rate(f"{here}: update_rate", self.update_rate, zero_ok=True)
        if self.is_camera:
            if self.camera is None:
                raise ConfigError(f"{here}: a {self.type} sensor needs a <camera>")
            self.camera.validate(here)
            if self.rate <= 0:
                raise ConfigError(f"{here}: update_rate must be > 0 Hz for a camera the cell renders, got 0")
        if self.ros_camera is not None:
            self.ros_camera.validate(here)


@dataclass
class JointStatePublisherPlugin:
    """``libgazebo_ros_joint_state_publisher.so``: ``/<namespace>/joint_states`` at its
    rate for its joints."""

    name: str = ""
    namespace: str = "/"
    update_rate: float = 100.0
    joint_names: list[str] = field(default_factory=list)

    def validate(self, where: str) -> None:
        _check_rate(f"{where}: plugin {self.name!r} update_rate", self.update_rate, zero_ok=False)
        if not self.joint_names:
            raise ConfigError(f"{where}: plugin {self.name!r} has no <joint_name>")


@dataclass
class JointPoseTrajectoryPlugin:
    """``libgazebo_ros_joint_pose_trajectory.so``: a ``trajectory_msgs/JointTrajectory`` on
    ``/<namespace>/<topic>`` sets the joints to each point's positions at its time."""

    name: str = ""
    namespace: str = "/"
    topic: str = "set_joint_trajectory"
    update_rate: float = 100.0

    def validate(self, where: str) -> None:
        _check_rate(f"{where}: plugin {self.name!r} update_rate", self.update_rate, zero_ok=False)
        if not self.topic:
            raise ConfigError(f"{where}: plugin {self.name!r} has an empty topic")


@dataclass
class PluginConfig:
    """A plugin the cell does not know: only named (one warning line for it)."""

    name: str = ""
    filename: str = ""
    #: The link of the sensor it sits on (empty: a model plugin).
    link: str = ""


@dataclass
class GazeboExtensions:
    """Everything a description's ``<gazebo>`` tags say."""

    materials: list[GazeboMaterial] = field(default_factory=list)
    frictions: list[LinkFriction] = field(default_factory=list)
    sensors: list[SensorConfig] = field(default_factory=list)
    joint_state_publishers: list[JointStatePublisherPlugin] = field(default_factory=list)
    joint_pose_trajectories: list[JointPoseTrajectoryPlugin] = field(default_factory=list)
    unknown_plugins: list[PluginConfig] = field(default_factory=list)
    #: ``gazebo_ros_control`` / ``gazebo_ros2_control`` (:mod:`omtp_drake.scenario.ros_control`).
    ros_control: Optional[RosControlConfig] = None

    def validate(self, where: str) -> None:
        """Raises ConfigError naming ``where`` (the file), the tag and the bad value."""
        for friction in self.frictions:
            friction.validate(where)
        names = [s.name for s in self.sensors]
        for sensor in self.sensors:
            sensor.validate(where)
            if names.count(sensor.name) > 1:
                raise ConfigError(f"{where}: sensor name {sensor.name!r} is used twice")
        for publisher in self.joint_state_publishers:
            publisher.validate(where)
        for trajectory in self.joint_pose_trajectories:
            trajectory.validate(where)
        if self.ros_control is not None:
            self.ros_control.validate(where)

    def links(self) -> set[str]:
        """The links the tags refer to."""
        links = {m.link for m in self.materials} | {f.link for f in self.frictions}
        return links | {s.link for s in self.sensors}

    def cameras(self) -> list[SensorConfig]:
        """The camera and depth sensors, in order."""
        return [s for s in self.sensors if s.is_camera]
