"""The course's Gazebo plugins, read from ``<gazebo>`` tags (URDF) and ``<plugin>`` /
``<sensor>`` elements (SDF), as the cell's systems with the plugin's parameters.

=============================  ====================================  ======================
plugin (``filename``)          becomes                               parameters read
=============================  ====================================  ======================
ROSLogicalCameraPlugin         a logical camera (``cameras``)        the ``logical_camera``
                                                                     sensor's near, far,
                                                                     horizontal_fov,
                                                                     aspect_ratio,
                                                                     update_rate;
                                                                     robotNamespace,
                                                                     image_topic_ros;
                                                                     position/orientation
                                                                     noise (gaussian);
                                                                     known_model_types,
                                                                     known_model_names,
                                                                     anonymize_models,
                                                                     model_frame_prefix
ROSVacuumGripperPlugin         the robot's suction gripper           grasp_check
                                                                     attach_steps;
                                                                     robot_namespace,
                                                                     control_topic,
                                                                     state_topic
ROSProximityRayPlugin          the break beam                        the ray sensor's range
                                                                     and update_rate;
                                                                     robotNamespace,
                                                                     output_state_topic,
                                                                     output_change_topic,
                                                                     frame_id
ROSConveyorBeltPlugin          the conveyor                          power;
                                                                     robot_namespace, topic
ObjectDisposalPlugin           the deletion wall                     update_rate
gazebo_ros_control             the arms' controllers, joint states   --
=============================  ====================================  ======================

The ROS names (topics, services, frame) are resolved as the plugin's node handle does
(:func:`omtp_drake.scenario.plugin_names.resolve_ros_name`) into the scenario's
``plugin_names``, which both transports serve.

A value the plugin's counterpart cannot take is one WorkspaceError naming the file and
the value; a plugin the cell has no counterpart for is one warning line (the caller
lists them in its report).
"""

from __future__ import annotations

import inspect
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import PurePath
from typing import Any

from omtp_drake.cell.conveyor import BreakBeam
from omtp_drake.errors import ConfigError, WorkspaceError
from omtp_drake.scenario import ConveyorConfig, LogicalCameraConfig
from omtp_drake.scenario.plugin_names import resolve_ros_name
from omtp_drake.sim.deletion_wall import DISPOSAL_PERIOD

#: Plugin library -> what it becomes in the cell.
KINDS = {
    "libROSLogicalCameraPlugin.so": "logical_camera",
    "libROSVacuumGripperPlugin.so": "suction",
    "libROSProximityRayPlugin.so": "break_beam",
    "libROSConveyorBeltPlugin.so": "conveyor",
    "libObjectDisposalPlugin.so": "deletion_wall",
    "libgazebo_ros_control.so": "controllers",
}


@dataclass(frozen=True)
class GazeboPlugin:
    """One ``<plugin>``: its library, name, element, the sensor it sits in (if any),
    the link it refers to ('' for the model) and where it was read."""

    filename: str
    name: str
    element: ET.Element
    sensor: ET.Element | None
    link: str
    where: str

    @property
    def kind(self) -> str | None:
        return KINDS.get(PurePath(self.filename).name)

    def text(self, path: str, default: str | None = None) -> str | None:
        found = self.element.findtext(path)
        return found.strip() if found is not None else default

    def unknown_line(self) -> str:
        return f"{self.where}: Gazebo plugin {self.filename} ({self.name}): not in the cell; ignored"


def plugins_in(element: ET.Element, where: str, link: str = "") -> list[GazeboPlugin]:
    """The plugins in ``element`` (a ``<gazebo>``, ``<model>`` or ``<link>``): its own and
    its sensors'."""
    found = []
    for child in element:
        if child.tag == "plugin":
            found.append(
                GazeboPlugin(child.get("filename", ""), child.get("name", ""), child, None, link, where)
            )
        elif child.tag == "sensor":
            for plugin in child.findall("plugin"):
                found.append(
                    GazeboPlugin(
                        plugin.get("filename", ""), plugin.get("name", ""), plugin, child, link, where
                    )
                )
    return found


def _number(text: str | None, where: str, what: str) -> float:
    try:
        value = float(text if text is not None else "nan")
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise WorkspaceError(f"{where}: {what} must be a number, got {text!r}")
    return value


def _noise_sigma(plugin: GazeboPlugin, tag: str) -> float:
    noise = plugin.element.find(f"{tag}/noise")
    if noise is None:
        return 0.0
    kind = (noise.findtext("type") or "").strip()
    if kind != "gaussian":
        raise WorkspaceError(f"{plugin.where}: {tag} type {kind!r} is not supported; valid: gaussian")
    mean = _number(noise.findtext("mean", "0"), plugin.where, f"{tag} mean")
    if mean != 0:
        raise WorkspaceError(f"{plugin.where}: {tag} mean {mean} is not supported; valid: 0")
    return _number(noise.findtext("stddev"), plugin.where, f"{tag} stddev")


def logical_camera(plugin: GazeboPlugin, sensor: ET.Element, name: str, xyz, rpy) -> dict:
    """The scenario's camera entry of a ROSLogicalCameraPlugin and its ``logical_camera``
    sensor, at ``xyz``/``rpy`` in world."""
    where = plugin.where
    values = sensor.find("logical_camera")
    if values is None:
        raise WorkspaceError(f"{where}: sensor {sensor.get('name')!r} has no <logical_camera> values")
    entry: dict[str, Any] = {
        "name": name,
        "xyz": [float(v) for v in xyz],
        "rpy": [float(v) for v in rpy],
        "near": _number(values.findtext("near"), where, "near"),
        "far": _number(values.findtext("far"), where, "far"),
        "horizontal_fov": _number(values.findtext("horizontal_fov"), where, "horizontal_fov"),
        "aspect_ratio": _number(values.findtext("aspect_ratio"), where, "aspect_ratio"),
        "update_rate_hz": _number(sensor.findtext("update_rate", "10"), where, "update_rate"),
        "position_noise_sigma": _noise_sigma(plugin, "position_noise"),
        "orientation_noise_sigma": _noise_sigma(plugin, "orientation_noise"),
    }
    config = LogicalCameraConfig(**entry)
    try:
        config.validate()
    except ConfigError as e:
        raise WorkspaceError(f"{where}: {e}") from None
    return entry


def suction_checks(plugin: GazeboPlugin) -> int:
    """The consecutive contact checks before a part attaches: the plugin attaches when its
    counter exceeds ``attach_steps``, i.e. on check ``attach_steps + 1``."""
    steps = _number(plugin.text("grasp_check/attach_steps", "1"), plugin.where, "grasp_check/attach_steps")
    contacts = _number(plugin.text("grasp_check/min_contact_count", "1"), plugin.where, "min_contact_count")
    if steps < 0 or not steps.is_integer():
        raise WorkspaceError(
            f"{plugin.where}: grasp_check/attach_steps must be an integer >= 0, got {steps:g}"
        )
    if contacts != 1:
        raise WorkspaceError(
            f"{plugin.where}: grasp_check/min_contact_count {contacts:g} is not supported; valid: 1"
        )
    return int(steps) + 1


def conveyor_power(plugin: GazeboPlugin) -> float:
    """The belt's power at start (ROSConveyorBeltPlugin ``power``, 0..100)."""
    power = _number(plugin.text("power", "0"), plugin.where, "power")
    try:
        ConveyorConfig(power=power).validate()
    except ConfigError as e:
        raise WorkspaceError(f"{plugin.where}: ROSConveyorBeltPlugin {e}") from None
    return power


def _defaults_of(function) -> dict[str, float]:
    return {
        k: p.default for k, p in inspect.signature(function).parameters.items() if p.default is not p.empty
    }


def check_break_beam(plugin: GazeboPlugin) -> None:
    """The ray sensor of a ROSProximityRayPlugin has the cell's beam's range and rate."""
    sensor = plugin.sensor
    if sensor is None:
        raise WorkspaceError(f"{plugin.where}: ROSProximityRayPlugin must sit in a ray sensor")
    cell = _defaults_of(BreakBeam.__init__)
    read = {
        "min_range": _number(sensor.findtext("ray/range/min"), plugin.where, "ray range min"),
        "max_range": _number(sensor.findtext("ray/range/max"), plugin.where, "ray range max"),
        "rate_hz": _number(sensor.findtext("update_rate", "10"), plugin.where, "update_rate"),
    }
    for key, value in read.items():
        if abs(value - cell[key]) > 1e-9:
            raise WorkspaceError(
                f"{plugin.where}: break beam {key} {value:g} is not supported; the cell's beam has "
                f"range ({cell['min_range']:g}, {cell['max_range']:g}) at {cell['rate_hz']:g} Hz"
            )


def check_deletion_wall(plugin: GazeboPlugin) -> None:
    """An ObjectDisposalPlugin checks at the cell's rate (the course's 5 Hz)."""
    rate = _number(plugin.text("update_rate", str(1 / DISPOSAL_PERIOD)), plugin.where, "update_rate")
    if abs(rate * DISPOSAL_PERIOD - 1) > 1e-6:
        raise WorkspaceError(
            f"{plugin.where}: ObjectDisposalPlugin update_rate {rate:g} is not supported; valid: "
            f"{1 / DISPOSAL_PERIOD:g} (the cell's deletion wall)"
        )


def disposal_collision(plugin: GazeboPlugin, model: ET.Element) -> str:
    """``link::collision`` of the wall ``model`` whose contacts an ObjectDisposalPlugin acts
    on, as the course's SideContactPlugin finds it: the ``<contact>`` sensor named by its
    ``contact_sensor_name`` on a link of the model, watching its one ``<collision>``
    (``__default__``: the link's first). '' when that sensor watches no single collision
    (Gazebo logs "requires a single collision" and the plugin disposes of nothing). No
    such sensor is one WorkspaceError (Gazebo's plugin cannot load without it)."""
    name = plugin.text("contact_sensor_name", "") or ""
    sensors = {
        s.get("name", ""): (link, s)
        for link in model.iter("link")
        for s in link.findall("sensor")
        if s.get("type") == "contact"
    }
    if name not in sensors:
        valid = ", ".join(sorted(sensors)) or "none"
        raise WorkspaceError(
            f"{plugin.where}: ObjectDisposalPlugin ({plugin.name}) <contact_sensor_name> {name!r}: no "
            f"contact sensor of that name on a link of the model; valid: {valid}"
        )
    link, sensor = sensors[name]
    watched = [(c.text or "").strip() for c in sensor.findall("contact/collision")]
    if len(watched) != 1:
        return ""
    collision = watched[0]
    if collision == "__default__":
        first = link.find("collision")
        collision = first.get("name", "") if first is not None else ""
    if collision not in {c.get("name", "") for c in link.findall("collision")}:
        return ""  # (the sensor watches a collision the link has not: no contact reaches it)
    return f"{link.get('name', '')}::{collision}"


def _ros_name(plugin: GazeboPlugin, tag: str, default: str, namespace_tag: str) -> str:
    """The plugin's ``<tag>`` (``default`` when absent) in its ``<namespace_tag>``, resolved
    as its node handle does; a bad name is one WorkspaceError naming the plugin."""
    value = plugin.text(tag, default) or ""
    namespace = plugin.text(namespace_tag, "") or ""
    try:
        return resolve_ros_name(value, namespace)
    except ConfigError as e:
        what = namespace_tag if str(e).startswith("namespace") else tag
        raise WorkspaceError(
            f"{plugin.where}: {PurePath(plugin.filename).name} ({plugin.name}) <{what}>: {e}"
        ) from None


def gripper_names(plugin: GazeboPlugin, robot: str) -> dict[str, str]:
    """``robot``'s ROSVacuumGripperPlugin's names (the scenario's ``plugin_names.grippers``
    entry): its control service and state topic in its ``robot_namespace``."""
    return {
        "robot": robot,
        "plugin": plugin.name,
        "control_service": _ros_name(plugin, "control_topic", "gripper/control", "robot_namespace"),
        "state_topic": _ros_name(plugin, "state_topic", "gripper/state", "robot_namespace"),
    }


def beam_names(plugin: GazeboPlugin) -> dict[str, str]:
    """A ROSProximityRayPlugin's topics and frame, after its sensor by default."""
    sensor = plugin.sensor.get("name", "") if plugin.sensor is not None else ""
    frame = plugin.text("frame_id", f"{sensor}_frame") or ""
    if not frame or any(c.isspace() for c in frame):
        raise WorkspaceError(
            f"{plugin.where}: ROSProximityRayPlugin ({plugin.name}) <frame_id> {frame!r} is not valid; "
            "valid: a frame name without spaces"
        )
    return {
        "beam_state_topic": _ros_name(plugin, "output_state_topic", sensor, "robotNamespace"),
        "beam_change_topic": _ros_name(plugin, "output_change_topic", f"{sensor}_change", "robotNamespace"),
        "beam_frame_id": frame,
    }


def conveyor_service(plugin: GazeboPlugin) -> str:
    """A ROSConveyorBeltPlugin's control service in its ``robot_namespace``."""
    return _ros_name(plugin, "topic", "conveyor/control", "robot_namespace")


def camera_topic(plugin: GazeboPlugin, name: str) -> str:
    """A ROSLogicalCameraPlugin's topic: ``image_topic_ros`` (the model's name by default) in
    its ``robotNamespace`` (the course's models: ``omtp``, so ``/omtp/<model>``)."""
    return _ros_name(plugin, "image_topic_ros", name, "robotNamespace")


#: sdformat's spellings of a bool (``Param::Get<bool>``, case-insensitive).
_BOOLS = {"true": True, "1": True, "false": False, "0": False}


def camera_listing(plugin: GazeboPlugin) -> tuple[dict, list[str]]:
    """A ROSLogicalCameraPlugin's publishing rules (the scenario's
    ``plugin_names.camera_listings`` entry, :class:`~omtp_drake.scenario.plugin_names.CameraListing`)
    and the lines Gazebo would log for them: a ``<known_model_types>`` without ``<type>``
    stops the plugin's Load (it then publishes nothing); an ``activation_topic`` is a Gazebo
    transport topic nothing in the cell publishes on (the camera stays on)."""
    element, lines = plugin.element, []
    entry: dict[str, Any] = {}
    where = f"{plugin.where}: ROSLogicalCameraPlugin ({plugin.name})"
    types = element.find("known_model_types")
    if types is not None:
        entry["known_model_types"] = [(t.text or "").strip() for t in types.findall("type")]
        if not entry["known_model_types"]:
            lines.append(
                f"{where}: Unable to find <type> elements in the <known_model_types> section; "
                "the plugin stops loading, as Gazebo's: the camera publishes nothing"
            )
            entry["advertised"] = False
    names = element.find("known_model_names")
    if names is not None:
        entry["known_model_names"] = [(n.text or "").strip() for n in names.findall("name")]
    anonymize = plugin.text("anonymize_models")
    if anonymize is not None:
        if anonymize.lower() not in _BOOLS:
            raise WorkspaceError(
                f"{where} <anonymize_models> {anonymize!r} is not a bool; valid: true, false, 1, 0"
            )
        entry["anonymize_models"] = _BOOLS[anonymize.lower()]
    prefix = element.findtext("model_frame_prefix")
    if prefix is not None:
        if any(c.isspace() for c in prefix.strip()):
            raise WorkspaceError(
                f"{where} <model_frame_prefix> {prefix.strip()!r} is not valid; "
                "valid: a tf frame prefix without spaces"
            )
        entry["model_frame_prefix"] = prefix.strip()
    if plugin.text("activation_topic") is not None:
        lines.append(
            f"{where}: <activation_topic> {plugin.text('activation_topic')!r} is a Gazebo transport "
            "topic; nothing in the cell publishes on it, so the camera stays on"
        )
    return entry, lines
