"""The ROS names of the course's Gazebo plugins (part of the scenario YAML schema).

A student's ``<plugin>`` may rename what the course's ``omtp_gazebo`` plugins advertise;
:mod:`omtp_drake.launch.plugins` reads those parameters once, resolves them with
:func:`resolve_ros_name` as the plugin's ``ros::NodeHandle`` does, and writes the full
names here; the plugin layer (:mod:`omtp_drake.gazebo`) serves exactly these names on
both transports. The defaults are the course's files' names (a built-in scenario has no
``<plugin>`` to read):

=========================  =======================================  ==============================
plugin                     parameters (plugin default)              course's names (this default)
=========================  =======================================  ==============================
ROSVacuumGripperPlugin     ``robot_namespace`` (none),              ``/gripperN/control``,
                           ``control_topic`` (``gripper/control``), ``/gripperN/state``
                           ``state_topic`` (``gripper/state``)
ROSProximityRayPlugin      ``robotNamespace`` (none),               ``/break_beam_sensor``,
                           ``output_state_topic`` (the sensor),     ``/break_beam_sensor_change``,
                           ``output_change_topic`` (sensor_change), ``break_beam_sensor_frame``
                           ``frame_id`` (the sensor's ``_frame``)
ROSConveyorBeltPlugin      ``robot_namespace`` (none),              ``/omtp/conveyor/control``
                           ``topic`` (``conveyor/control``)
ROSLogicalCameraPlugin     ``robotNamespace`` (``/``),              ``/omtp/<camera>``
                           ``image_topic_ros`` (the model's name)
=========================  =======================================  ==============================

A logical camera's plugin also says which models it publishes and how it names them
(``known_model_types``, ``known_model_names``, ``anonymize_models``, ``model_frame_prefix``):
:class:`CameraListing`, one per camera a file set them for (the plugin layer's
:mod:`omtp_drake.gazebo.logical_camera` applies them).
"""

import re
from dataclasses import dataclass, field
from typing import Optional

from omtp_drake.errors import ConfigError

#: A ROS graph resource name as roscpp's ``names::validate`` takes it (a ``~`` name is
#: refused by a NodeHandle's advertise, which the plugins use).
_ROS_NAME = re.compile(r"/?[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*")
#: What a valid name is, for the error.
VALID_NAME = "a ROS name: letters, digits, '_' and '/', each part starting with a letter (no '~')"


def resolve_ros_name(name: str, namespace: str = "") -> str:
    """``name`` resolved in ``namespace`` (both relative to the root, as Gazebo's node
    ``/gazebo`` resolves them): an absolute name stays, a relative one goes under the
    namespace. A name or namespace that is no ROS name is one ConfigError."""
    space = re.sub("/+", "/", namespace).strip("/")
    if space and not _ROS_NAME.fullmatch(space):
        raise ConfigError(f"namespace {namespace!r} is not valid; valid: {VALID_NAME}")
    clean = re.sub("/+", "/", name).rstrip("/")
    if not _ROS_NAME.fullmatch(clean):
        raise ConfigError(f"name {name!r} is not valid; valid: {VALID_NAME}")
    if clean.startswith("/"):
        return clean
    return f"/{space}/{clean}" if space else f"/{clean}"


def check_name(what: str, name: str) -> None:
    """``name`` (a resolved name of the scenario) is absolute and valid."""
    if not name.startswith("/") or not _ROS_NAME.fullmatch(name):
        raise ConfigError(f"{what} {name!r} is not valid; valid: an absolute {VALID_NAME}")


#: A gripper's resolved names.
_GRIPPER_NAMES = ("control_service", "state_topic")
#: The course's gripper models, ``vacuum_gripperN``, whose plugins the course's xacro names
#: ``gripperN``.
_COURSE_GRIPPER = re.compile(r"vacuum_gripper(\d+)")


@dataclass
class GripperNames:
    """One arm's ROSVacuumGripperPlugin: its ``name`` and its resolved names."""

    #: The robot whose gripper it is.
    robot: str = ""
    #: The plugin's ``name`` attribute.
    plugin: str = ""
    control_service: str = ""
    state_topic: str = ""


@dataclass
class CameraListing:
    """What one ROSLogicalCameraPlugin publishes, as its ``<plugin>`` says (the defaults:
    every model in view, by its name, frames ``<camera>_<model>_frame``).

    Attributes:
        known_model_types: its ``<known_model_types>``' ``<type>``s (None: no such element).
        known_model_names: its ``<known_model_names>``' ``<name>``s (None: no such element).
            With either, only models of a listed type or name are published.
        anonymize_models: every model's type is ``model``, its frame ``model_<id>``.
        model_frame_prefix: the prefix of the models' tf frames (None: ``<camera>_``).
        advertised: False when the plugin stopped loading (a ``<known_model_types>``
            without ``<type>``: Gazebo logs an error and the camera publishes nothing).
    """

    known_model_types: Optional[list[str]] = None
    known_model_names: Optional[list[str]] = None
    anonymize_models: bool = False
    model_frame_prefix: Optional[str] = None
    advertised: bool = True

    def frame_prefix(self, camera: str) -> str:
        """The prefix of the tf frames of the models ``camera`` publishes."""
        return self.model_frame_prefix if self.model_frame_prefix is not None else f"{camera}_"


@dataclass
class PluginNames:
    """The course's plugins' ROS names (the module doc's table)."""

    #: The grippers whose plugin a file set (an arm not listed: ``/gripperN/...``).
    grippers: list[GripperNames] = field(default_factory=list)
    beam_state_topic: str = "/break_beam_sensor"
    beam_change_topic: str = "/break_beam_sensor_change"
    beam_frame_id: str = "break_beam_sensor_frame"
    conveyor_control_service: str = "/omtp/conveyor/control"
    #: Logical camera -> its topic (a camera not listed: ``/omtp/<camera>``).
    camera_topics: dict[str, str] = field(default_factory=dict)
    #: Logical camera -> what it publishes (a camera not listed: the defaults).
    camera_listings: dict[str, CameraListing] = field(default_factory=dict)

    def camera_listing(self, camera: str) -> CameraListing:
        """What ``camera``'s plugin publishes."""
        return self.camera_listings.get(camera, CameraListing())

    def camera_topic(self, camera: str) -> str:
        """``camera``'s topic."""
        return self.camera_topics.get(camera, f"/omtp/{camera}")

    def gripper(self, robot: str, model: str = "") -> Optional["GripperNames"]:
        """``robot``'s gripper's names: as a file set them, else the course's for its gripper
        ``model`` (``/gripperN/...`` for ``vacuum_gripperN``; None for another model)."""
        found = next((g for g in self.grippers if g.robot == robot), None)
        return found if found is not None else course_gripper(robot, model)

    def without_defaults(self, grippers: dict[str, str]) -> dict:
        """The entries that differ from the defaults (``grippers``: robot -> its gripper
        model), as a scenario document's ``plugin_names``: a file that names its plugins as
        the course does gives the scenario the course's files give."""
        default = PluginNames()
        out: dict = {
            key: value
            for key, value in vars(self).items()
            if key not in ("grippers", "camera_topics", "camera_listings") and value != getattr(default, key)
        }
        own = [vars(g) for g in self.grippers if g != course_gripper(g.robot, grippers.get(g.robot, ""))]
        cameras = {c: t for c, t in self.camera_topics.items() if t != default.camera_topic(c)}
        out.update({"grippers": own} if own else {}, **({"camera_topics": cameras} if cameras else {}))
        listings = {c: vars(v) for c, v in self.camera_listings.items() if v != CameraListing()}
        out.update({"camera_listings": listings} if listings else {})
        return out

    def validate(self) -> None:
        names = [
            (f"plugin_names.grippers[{g.robot}].control_service", g.control_service) for g in self.grippers
        ]
        names += [(f"plugin_names.grippers[{g.robot}].state_topic", g.state_topic) for g in self.grippers]
        names += [
            ("plugin_names.beam_state_topic", self.beam_state_topic),
            ("plugin_names.beam_change_topic", self.beam_change_topic),
            ("plugin_names.conveyor_control_service", self.conveyor_control_service),
        ]
        names += [(f"plugin_names.camera_topics[{c}]", t) for c, t in self.camera_topics.items()]
        for what, name in names:
            check_name(what, name)
        for camera, listing in self.camera_listings.items():
            prefix = listing.model_frame_prefix
            if prefix is not None and any(c.isspace() for c in prefix):
                raise ConfigError(
                    f"plugin_names.camera_listings[{camera}].model_frame_prefix {prefix!r} is not valid; "
                    "valid: a tf frame prefix without spaces"
                )
        services = [g.control_service for g in self.grippers] + [self.conveyor_control_service]
        twice = sorted({s for s in services if services.count(s) > 1})
        if twice:
            raise ConfigError(
                f"plugin_names: service {twice[0]!r} is advertised twice; each plugin needs its own"
            )


def course_gripper(robot: str, model: str) -> Optional[GripperNames]:
    """The course's names of the gripper ``model`` on ``robot`` (None: not the course's)."""
    match = _COURSE_GRIPPER.fullmatch(model)
    if match is None:
        return None
    name = f"gripper{match.group(1)}"
    return GripperNames(robot, name, f"/{name}/control", f"/{name}/state")
