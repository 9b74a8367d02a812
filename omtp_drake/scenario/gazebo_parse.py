"""Reading a description's Gazebo tags into :class:`~omtp_drake.scenario.gazebo_tags.GazeboExtensions`.

A URDF holds them in ``<gazebo>`` elements (``reference="LINK"`` for a link's material,
friction and sensors; none for the model's plugins); an SDF model holds the same
sensors in its ``<link>`` elements and its plugins in ``<model>``. Values are read as
Gazebo reads them (numbers, ``true``/``1``); one that is not a number is a ConfigError
naming the file, the tag and the text. What the values mean is checked apart, by
:meth:`GazeboExtensions.validate`.
"""

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError
from omtp_drake.scenario.gazebo_tags import (
    CameraSettings,
    GazeboExtensions,
    GazeboMaterial,
    JointPoseTrajectoryPlugin,
    JointStatePublisherPlugin,
    LinkFriction,
    PluginConfig,
    RosCameraPlugin,
    SensorConfig,
)
from omtp_drake.scenario.ros_control_parse import is_ros_control_plugin, parse_ros_control

CAMERA_PLUGIN = "libgazebo_ros_camera.so"
JOINT_STATE_PLUGIN = "libgazebo_ros_joint_state_publisher.so"
JOINT_POSE_TRAJECTORY_PLUGIN = "libgazebo_ros_joint_pose_trajectory.so"


class _Reader:
    """Typed reads of one file's elements (errors name the file)."""

    def __init__(self, where: str):
        self.where = where

    def text(self, element: ET.Element, *paths: str, default: str = "") -> str:
        """The text of the first of ``paths`` under ``element`` (ROS 2 and ROS 1 spellings)."""
        for path in paths:
            found = element.find(path)
            if found is not None and found.text is not None:
                return found.text.strip()
        return default

    def number(self, element: ET.Element, *paths: str, default: float) -> float:
        text = self.text(element, *paths)
        if not text:
            return default
        try:
            return float(text)
        except ValueError:
            raise ConfigError(f"{self.where}: <{paths[0]}> {text!r} is not a number") from None

    def integer(self, element: ET.Element, path: str, default: int) -> int:
        value = self.number(element, path, default=default)
        if value != int(value):
            raise ConfigError(f"{self.where}: <{path}> {value} is not a whole number")
        return int(value)

    def flag(self, element: ET.Element, path: str) -> bool:
        return self.text(element, path).lower() in ("true", "1")

    def pose(self, element: ET.Element) -> tuple[list[float], list[float]]:
        text = self.text(element, "pose")
        if not text:
            return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        try:
            values = [float(x) for x in text.split()]
        except ValueError:
            values = []
        if len(values) != 6:
            raise ConfigError(f"{self.where}: <pose> {text!r} needs 6 numbers (x y z roll pitch yaw)")
        return values[:3], values[3:]


def parse_gazebo_tags(text: str, where: str) -> GazeboExtensions:
    """The Gazebo tags of the URDF or SDF ``text`` (``where``: its file, for errors)."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise ConfigError(f"{where}: not well-formed XML: {e}") from None
    read = _Reader(where)
    out = GazeboExtensions()
    if root.tag == "robot":
        links = [link.get("name", "") for link in root.findall("link")]
        joints = {joint.get("name", "") for joint in root.findall("joint")}
        for gazebo in root.findall("gazebo"):
            reference = gazebo.get("reference", "")
            if reference and reference not in links:
                _check_unknown_reference(gazebo, reference, links, joints, text, where)
            elif reference:
                _link_tags(read, gazebo, reference, out)
            for plugin in gazebo.findall("plugin"):
                _model_plugin(read, plugin, out)
        out.ros_control = parse_ros_control(root, where)
        return out
    for model in root.iter("model"):
        for link in model.findall("link"):
            for sensor in link.findall("sensor"):
                out.sensors.append(_sensor(read, sensor, link.get("name", ""), out))
        for plugin in model.findall("plugin"):
            _model_plugin(read, plugin, out)
    return out


def _check_unknown_reference(
    gazebo: ET.Element, reference: str, links: list[str], joints: set[str], text: str, where: str
) -> None:
    """A ``<gazebo reference>`` that names no link. One that names nothing: Gazebo's URDF
    reader drops it without a word, so a sensor or plugin in it would silently not exist.
    A joint's: Gazebo gives the joint its physics settings, and a sensor there is a joint
    sensor (force-torque), which this cell has not. Either is one error naming the file,
    the line and the links (a material or friction alone is left out, as Gazebo does)."""
    if reference in joints:
        if gazebo.find("sensor") is None:
            return
        named = "is a joint; a sensor sits on a link here (joint sensors are not simulated)"
    elif gazebo.find("sensor") is None and gazebo.find("plugin") is None:
        return
    else:
        named = "no link or joint of that name"
    raise ConfigError(
        f"{reference_line(where, text, reference)}: <gazebo reference={reference!r}>: {named}; "
        f"valid links: {', '.join(links)}"
    )


def reference_line(where: str, text: str, reference: str) -> str:
    """``file:line`` of ``reference="NAME"``: in the file ``where`` when it is written there
    (a xacro's own line), else in a xacro or URDF beside it or below its folder (the file a
    xacro includes), else in the expanded ``text``."""
    needle = f'reference="{reference}"'
    top = Path(where)
    files = [top]
    if top.is_file():
        files += sorted(p for p in top.parent.rglob("*") if p.suffix in (".xacro", ".urdf") and p != top)
    for path in files:
        try:
            source = path.read_text()
        except (OSError, UnicodeDecodeError):
            continue
        index = source.find(needle)
        if index >= 0:
            return f"{path}:{source.count(chr(10), 0, index) + 1}"
    index = text.find(needle)
    return f"{where}:{text.count(chr(10), 0, index) + 1}" if index >= 0 else where


def _link_tags(read: _Reader, gazebo: ET.Element, link: str, out: GazeboExtensions) -> None:
    material = read.text(gazebo, "material")
    if material:
        out.materials.append(GazeboMaterial(link=link, name=material))
    if gazebo.find("mu1") is not None or gazebo.find("mu2") is not None:
        mu1 = read.number(gazebo, "mu1", default=1.0)
        out.frictions.append(LinkFriction(link=link, mu1=mu1, mu2=read.number(gazebo, "mu2", default=mu1)))
    for sensor in gazebo.findall("sensor"):
        out.sensors.append(_sensor(read, sensor, link, out))


def _sensor(read: _Reader, element: ET.Element, link: str, out: GazeboExtensions) -> SensorConfig:
    xyz, rpy = read.pose(element)
    sensor = SensorConfig(
        name=element.get("name", ""),
        type=element.get("type", ""),
        link=link,
        xyz=xyz,
        rpy=rpy,
        update_rate=read.number(element, "update_rate", default=0.0),
        always_on=read.flag(element, "always_on"),
        visualize=read.flag(element, "visualize"),
    )
    camera = element.find("camera")
    if camera is not None:
        sensor.camera = _camera(read, camera)
    for plugin in element.findall("plugin"):
        if plugin.get("filename", "").endswith(CAMERA_PLUGIN) and sensor.is_camera:
            sensor.ros_camera = _camera_plugin(read, plugin, sensor)
        else:
            out.unknown_plugins.append(_unknown(plugin, link))
    return sensor


def _camera(read: _Reader, camera: ET.Element) -> CameraSettings:
    return CameraSettings(
        horizontal_fov=read.number(camera, "horizontal_fov", default=1.047),
        width=read.integer(camera, "image/width", 320),
        height=read.integer(camera, "image/height", 240),
        format=read.text(camera, "image/format", default="R8G8B8"),
        near=read.number(camera, "clip/near", default=0.1),
        far=read.number(camera, "clip/far", default=100.0),
        noise_type=read.text(camera, "noise/type", default="none"),
        noise_mean=read.number(camera, "noise/mean", default=0.0),
        noise_stddev=read.number(camera, "noise/stddev", default=0.0),
    )


def _camera_plugin(read: _Reader, plugin: ET.Element, sensor: SensorConfig) -> RosCameraPlugin:
    return RosCameraPlugin(
        name=plugin.get("name", ""),
        camera_name=read.text(plugin, "camera_name", "cameraName", default=sensor.name),
        namespace=_namespace(read, plugin),
        frame_name=read.text(plugin, "frame_name", "frameName", default=sensor.link),
        min_depth=read.number(plugin, "min_depth", default=0.4),
        max_depth=_optional(read.number(plugin, "max_depth", default=math.inf)),
        update_rate=read.number(plugin, "update_rate", "updateRate", default=0.0),
    )


def _optional(value: float) -> Optional[float]:
    return None if value == math.inf else value


def _namespace(read: _Reader, plugin: ET.Element) -> str:
    """``<ros><namespace>`` (ROS 2) or ``<robotNamespace>`` (ROS 1), as an absolute name."""
    namespace = read.text(plugin, "ros/namespace", "robotNamespace", default="/")
    return "/" + namespace.strip("/")


def _model_plugin(read: _Reader, plugin: ET.Element, out: GazeboExtensions) -> None:
    filename = plugin.get("filename", "")
    name = plugin.get("name", "")
    if filename.endswith(JOINT_STATE_PLUGIN):
        joints = [e.text.strip() for e in plugin.findall("joint_name") if e.text]
        ros1 = read.text(plugin, "jointName")
        joints += [j.strip() for j in ros1.split(",") if j.strip()]
        out.joint_state_publishers.append(
            JointStatePublisherPlugin(
                name=name,
                namespace=_namespace(read, plugin),
                update_rate=read.number(plugin, "update_rate", "updateRate", default=100.0),
                joint_names=joints,
            )
        )
    elif filename.endswith(JOINT_POSE_TRAJECTORY_PLUGIN):
        out.joint_pose_trajectories.append(
            JointPoseTrajectoryPlugin(
                name=name,
                namespace=_namespace(read, plugin),
                topic=read.text(plugin, "topicName", default="set_joint_trajectory"),
                update_rate=read.number(plugin, "update_rate", "updateRate", default=100.0),
            )
        )
    elif not is_ros_control_plugin(filename):
        out.unknown_plugins.append(_unknown(plugin, ""))


def _unknown(plugin: ET.Element, link: str) -> PluginConfig:
    return PluginConfig(name=plugin.get("name", ""), filename=plugin.get("filename", ""), link=link)


def description_format(text: str, where: str) -> str:
    """``urdf`` or ``sdf``: the format of a description by its root element."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise ConfigError(f"{where}: not well-formed XML: {e}") from None
    formats = {"robot": "urdf", "sdf": "sdf"}
    if root.tag not in formats:
        raise ConfigError(f"{where}: root element <{root.tag}>; valid: <robot> (URDF), <sdf> (SDF)")
    return formats[root.tag]


def root_name(text: str) -> Optional[str]:
    """The ``name`` of a URDF's ``<robot>`` or an SDF's first ``<model>``."""
    root = ET.fromstring(text)
    if root.tag == "robot":
        return root.get("name")
    model = root.find("model") if root.tag == "sdf" else None
    return model.get("name") if model is not None else None


def check_masses(text: str, where: str) -> None:
    """The numbers Gazebo's readers refuse and Drake's parser lets by (it reads ``size="abc
    0.1 0.1"`` as a box and only warns of a negative inertia): each link's ``<inertial>``
    mass (> 0) and inertia (finite, its moments >= 0), each box's size, sphere's and
    cylinder's radius and length (> 0), each URDF ``<origin>``'s ``xyz``/``rpy`` and SDF
    ``<pose>`` (finite). One ConfigError naming the file, the link and the value."""
    root = ET.fromstring(text)
    urdf = root.tag == "robot"
    for link in root.iter("link"):
        name = link.get("name", "")
        mass = link.find("inertial/mass")
        if mass is not None:
            _check_numbers(
                where, name, "inertial mass", (mass.get("value") if urdf else mass.text), 1, positive=True
            )
        inertia = link.find("inertial/inertia")
        for key in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz") if inertia is not None else ():
            value = inertia.get(key) if urdf else inertia.findtext(key)  # type: ignore[union-attr]
            if value is not None:
                _check_numbers(
                    where, name, f"inertia {key}", value, 1, positive=key in ("ixx", "iyy", "izz"), zero=True
                )
        for box in link.iter("box"):
            _check_numbers(
                where, name, "box size", box.get("size") if urdf else box.findtext("size"), 3, positive=True
            )
        for shape in [*link.iter("sphere"), *link.iter("cylinder")]:
            for key in ("radius", "length") if shape.tag == "cylinder" else ("radius",):
                value = shape.get(key) if urdf else shape.findtext(key)
                _check_numbers(where, name, f"{shape.tag} {key}", value, 1, positive=True)
        for pose in link.iter("pose") if not urdf else ():
            if (pose.text or "").strip():
                _check_numbers(where, name, "pose", pose.text, 6)
        for origin in link.iter("origin"):
            for key in ("xyz", "rpy"):
                if origin.get(key) is not None:
                    _check_numbers(where, name, f"origin {key}", origin.get(key), 3)
    for joint in root.iter("joint") if urdf else ():
        for origin in joint.findall("origin"):
            for key in ("xyz", "rpy"):
                if origin.get(key) is not None:
                    _check_numbers(
                        where, joint.get("name", ""), f"origin {key}", origin.get(key), 3, what="joint"
                    )


def _check_numbers(
    where: str,
    owner: str,
    key: str,
    text: Optional[str],
    count: int,
    *,
    positive: bool = False,
    zero: bool = False,
    what: str = "link",
) -> None:
    """``text`` holds ``count`` finite numbers (> 0 with ``positive``, >= 0 with ``zero`` too)."""
    try:
        values = [float(v) for v in (text or "").split()]
    except ValueError:
        values = []
    ok = len(values) == count and all(math.isfinite(v) for v in values)
    if ok and positive:
        ok = all(v >= 0 if zero else v > 0 for v in values)
    if not ok:
        need = f"{count} finite number{'s' if count > 1 else ''}" + (
            " >= 0" if positive and zero else " > 0" if positive else ""
        )
        raise ConfigError(f"{where}: {what} {owner!r}: {key} {(text or '').strip()!r} must be {need}")
