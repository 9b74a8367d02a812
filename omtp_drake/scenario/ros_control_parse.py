"""Reading a robot's ros_control / ros2_control set-up into :class:`RosControlConfig`.

- :func:`parse_ros_control`: the URDF's ``gazebo_ros_control`` or ``gazebo_ros2_control``
  plugin, its ``<transmission>``\\ s (ROS 1) or its ``<ros2_control>`` tag (ROS 2); the
  ROS 2 plugin's ``<parameters>`` YAML is read too, and every controller it declares
  is started (as ``controller_manager``'s spawner would start each in a launch file).
- :func:`with_controllers`: a controllers YAML of either form (ROS 1: a mapping
  of controller names to their ``type`` and parameters, at the top or under the
  namespace; ROS 2: ``controller_manager: ros__parameters:`` and one
  ``NAME: ros__parameters:`` per controller), with the controllers a spawner starts.

Values are read as the controllers read them; a value of the wrong type is a
ConfigError naming the file and the key. What they mean is checked apart
(:meth:`RosControlConfig.validate`).
"""

import dataclasses
import logging
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Optional

import yaml

from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario.ros_control import (
    CONTROLLER_TYPES,
    ControllerConfig,
    HardwareJoint,
    JointTolerance,
    PidGains,
    RosControlConfig,
)

_log = logging.getLogger("gazebo")

ROS1_PLUGIN = "libgazebo_ros_control.so"
ROS2_PLUGIN = "libgazebo_ros2_control.so"
PLUGINS = (ROS1_PLUGIN, ROS2_PLUGIN)
#: ``hardwareInterface`` of a transmission -> the joint's command interface.
HARDWARE_INTERFACES = {
    "PositionJointInterface": "position",
    "VelocityJointInterface": "velocity",
    "EffortJointInterface": "effort",
}


def is_ros_control_plugin(filename: str) -> bool:
    return filename.endswith(PLUGINS)


def parse_ros_control(root: ET.Element, where: str) -> Optional[RosControlConfig]:
    """The ros_control set-up of the URDF ``root`` (None: it has no such plugin)."""
    plugin = next(
        (p for p in root.findall("gazebo/plugin") if is_ros_control_plugin(p.get("filename", ""))), None
    )
    if plugin is None:
        return None
    if plugin.get("filename", "").endswith(ROS1_PLUGIN):
        namespace = (plugin.findtext("robotNamespace") or "/").strip() or "/"
        period = _number(plugin.findtext("controlPeriod"), where, "controlPeriod", 0.0)
        return RosControlConfig(
            plugin="gazebo_ros_control",
            namespace=namespace,
            update_rate=1.0 / period if period > 0 else 0.0,
            joints=_transmission_joints(root, where),
        )
    namespace = (plugin.findtext("ros/namespace") or "/").strip() or "/"
    config = RosControlConfig(
        plugin="gazebo_ros2_control", namespace=namespace, joints=_ros2_joints(root, where)
    )
    for element in plugin.findall("parameters"):
        path = (element.text or "").strip()
        if not Path(path).is_file():
            # gazebo_ros2_control's controller manager fails to start on it; Gazebo goes on.
            _log.warning("%s: gazebo_ros2_control <parameters> %r: no such file; no controllers", where, path)
            continue
        declared = with_controllers(config, Path(path).read_text(), path, refuse_conflicts=False)
        config = dataclasses.replace(declared, declared=declared.controllers, controllers=[])
        config = spawned_only(config, [c.name for c in config.declared], path, refuse_conflicts=False)
    return config


def spawned_only(
    config: RosControlConfig, names: Sequence[str], where: str, *, refuse_conflicts: bool = True
) -> RosControlConfig:
    """ROS 2: ``config`` with the declared controllers ``names`` active, in that order (a
    launch's ``controller_manager`` spawners' arguments). A controller claiming a joint an
    earlier one holds is refused (ConfigError), or, with ``refuse_conflicts`` False, left
    inactive with one warning line, as the controller manager refuses to activate it."""
    declared = {c.name: c for c in config.declared}
    for name in names:
        if name not in declared:
            raise UnknownNameError(f"{where}: controller", name, declared)
    active: list[ControllerConfig] = []
    claimed: dict[str, str] = {}
    for name in names:
        controller = declared[name]
        joints = controller.joints if controller.kind != "joint_states" else []
        holder = next((claimed[j] for j in joints if j in claimed), None)
        if holder is not None:
            line = (
                f"{where}: controller {name!r} not activated: {holder!r} holds its joints (resource conflict)"
            )
            if refuse_conflicts:
                raise ConfigError(line)
            _log.warning(line)
            continue
        claimed |= dict.fromkeys(joints, name)
        active.append(controller)
    out = dataclasses.replace(config, controllers=active)
    out.validate(where)
    return out


def with_controllers(
    config: RosControlConfig,
    text: str,
    file: str,
    names: Optional[Sequence[str]] = None,
    *,
    refuse_conflicts: bool = True,
) -> RosControlConfig:
    """``config`` with the controllers of the YAML ``text`` (from ``file``) started:
    ``names`` (a spawner's arguments; None: every controller the YAML declares)."""
    return with_controller_params(
        config, _yaml_mapping(text, file), file, names, refuse_conflicts=refuse_conflicts
    )


def with_controller_params(
    config: RosControlConfig,
    document: dict,
    file: str,
    names: Optional[Sequence[str]] = None,
    *,
    refuse_conflicts: bool = True,
) -> RosControlConfig:
    """``config`` with the controllers of the parameters ``document`` (a controllers YAML
    as loaded, or a launch's parameters under the namespace; ``file`` names where) started."""
    update_rate, controllers = controllers_from_params(document, file, config, names)
    out = dataclasses.replace(
        config,
        parameters=file,
        update_rate=update_rate if update_rate is not None else config.update_rate,
        controllers=[*config.controllers, *controllers],
    )
    if refuse_conflicts:
        out.validate(file)
    return out


def _yaml_mapping(text: str, file: str) -> dict:
    try:
        document = yaml.safe_load(text) or {}
    except yaml.YAMLError as e:
        raise ConfigError(f"{file}: not valid YAML: {str(e).splitlines()[0]}") from None
    if not isinstance(document, dict):
        raise ConfigError(f"{file}: a controllers YAML is a mapping, got {type(document).__name__}")
    return document


def controllers_from_params(
    document: dict, file: str, config: RosControlConfig, names: Optional[Sequence[str]] = None
) -> tuple[Optional[float], list[ControllerConfig]]:
    """(the controller manager's ``update_rate`` if the parameters set one, the started controllers)."""
    document = {str(k).strip("/"): v for k, v in document.items()}
    namespace = config.namespace.strip("/")
    if namespace in document and isinstance(document[namespace], dict) and "type" not in document[namespace]:
        document = {str(k).strip("/"): v for k, v in document[namespace].items()}
    if "controller_manager" in document:
        return _ros2_controllers(document, file, config, names)
    declared = {k: v for k, v in document.items() if isinstance(v, dict) and "type" in v}
    started = [_controller(name, params, file, config) for name, params in _pick(declared, names, file)]
    return None, started


def _ros2_controllers(
    document: dict, file: str, config: RosControlConfig, names: Optional[Sequence[str]]
) -> tuple[Optional[float], list[ControllerConfig]]:
    manager = _ros_parameters(document["controller_manager"], file, "controller_manager")
    rate = manager.get("update_rate")
    declared = {k: v for k, v in manager.items() if isinstance(v, dict) and "type" in v}
    started = []
    for name, entry in _pick(declared, names, file):
        params = {"type": entry["type"], **_ros_parameters(document.get(name, {}), file, name)}
        started.append(_controller(name, params, file, config))
    return (None if rate is None else _number(rate, file, "update_rate", 0.0)), started


def _ros_parameters(entry: Any, file: str, name: str) -> dict:
    params = entry.get("ros__parameters", {}) if isinstance(entry, dict) else None
    if not isinstance(params, dict):
        raise ConfigError(f"{file}: {name}: ros__parameters must be a mapping")
    return params


def _pick(declared: dict, names: Optional[Sequence[str]], file: str) -> list[tuple[str, dict]]:
    if names is None:
        return list(declared.items())
    for name in names:
        if name not in declared:
            raise UnknownNameError(f"{file}: controller", name, declared)
    return [(name, declared[name]) for name in names]


def _controller(name: str, params: dict, file: str, config: RosControlConfig) -> ControllerConfig:
    where = f"{file}: {name}"
    kind_type = str(params.get("type", ""))
    if kind_type not in CONTROLLER_TYPES:
        raise UnknownNameError(f"{where}: controller type", kind_type, CONTROLLER_TYPES)
    kind, interface = CONTROLLER_TYPES[kind_type]
    joints = params.get("joints", [params["joint"]] if "joint" in params else [])
    if not isinstance(joints, list):
        raise ConfigError(f"{where}: joints must be a list, got {joints!r}")
    if kind == "joint_states" and not joints:
        joints = [j.name for j in config.joints]
    if interface is None:
        interfaces = params.get("command_interfaces", [params.get("interface_name", "position")])
        interface = str(interfaces[0]) if isinstance(interfaces, list) and interfaces else str(interfaces)
    rate_key = "publish_rate" if "publish_rate" in params else "update_rate"
    gains = params.get("gains", {})
    if "pid" in params and len(joints) == 1:
        gains = {joints[0]: params["pid"]}
    return ControllerConfig(
        name=name,
        type=kind_type,
        joints=[str(j) for j in joints],
        interface=interface,
        publish_rate=_number(params.get(rate_key), where, rate_key, 0.0),
        state_publish_rate=_number(params.get("state_publish_rate"), where, "state_publish_rate", 50.0),
        **_constraints(params.get("constraints", {}), where),
        gains={str(j): _gains(g, f"{where}: gains: {j}") for j, g in (gains or {}).items()},
    )


def _constraints(constraints: Any, where: str) -> dict:
    if not isinstance(constraints, dict):
        raise ConfigError(f"{where}: constraints must be a mapping, got {constraints!r}")
    tolerances = {
        str(joint): JointTolerance(
            trajectory=_number(value.get("trajectory"), where, f"constraints.{joint}.trajectory", 0.0),
            goal=_number(value.get("goal"), where, f"constraints.{joint}.goal", 0.0),
        )
        for joint, value in constraints.items()
        if isinstance(value, dict)
    }
    return {
        "goal_time": _number(constraints.get("goal_time"), where, "constraints.goal_time", 0.0),
        "stopped_velocity_tolerance": _number(
            constraints.get("stopped_velocity_tolerance"), where, "stopped_velocity_tolerance", 0.01
        ),
        "tolerances": tolerances,
    }


def _gains(value: Any, where: str) -> PidGains:
    if not isinstance(value, dict):
        raise ConfigError(f"{where}: gains must be a mapping of p, i, d, i_clamp, got {value!r}")
    keys = {"p": 0.0, "i": 0.0, "d": 0.0, "i_clamp": 0.0}
    return PidGains(**{k: _number(value.get(k), where, k, default) for k, default in keys.items()})


def _number(value: Any, where: str, key: str, default: float) -> float:
    if value is None:
        return default
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: {key} {value!r} is not a number") from None


def _transmission_joints(root: ET.Element, where: str) -> list[HardwareJoint]:
    joints = []
    for transmission in root.findall("transmission"):
        for joint in transmission.findall("joint"):
            texts = [(e.text or "").strip() for e in joint.findall("hardwareInterface")]
            texts += [(e.text or "").strip() for e in transmission.findall("actuator/hardwareInterface")]
            found = [
                HARDWARE_INTERFACES[t.rsplit("/", 1)[-1]]
                for t in texts
                if t.rsplit("/", 1)[-1] in HARDWARE_INTERFACES
            ]
            if not found:
                raise UnknownNameError(
                    f"{where}: hardwareInterface of transmission {transmission.get('name')!r}",
                    texts[0] if texts else "",
                    [f"hardware_interface/{k}" for k in HARDWARE_INTERFACES],
                )
            joints.append(HardwareJoint(name=joint.get("name", ""), command_interfaces=found[:1]))
    return joints


def _ros2_joints(root: ET.Element, where: str) -> list[HardwareJoint]:
    joints = []
    for joint in root.findall("ros2_control/joint"):
        commands = [c.get("name", "") for c in joint.findall("command_interface")]
        initial = None
        for state in joint.findall("state_interface"):
            if state.get("name") != "position":
                continue
            for param in state.findall("param"):
                if param.get("name") == "initial_value":
                    initial = _number((param.text or "").strip(), where, "initial_value", 0.0)
        joints.append(
            HardwareJoint(name=joint.get("name", ""), command_interfaces=commands, initial_position=initial)
        )
    return joints


def spawn_controllers(models: Sequence[Any], spec: str) -> list[Any]:
    """``models`` (ModelConfigs) with the controllers of ``spec`` started: ``FILE.yaml
    [NAME ...]``, a controllers YAML loaded as ``rosparam load`` does and the named
    controllers started as ``controller_manager``'s ``spawner NAME ...`` does (no name:
    every one of the file), on the one model that has a ros_control plugin."""
    file, *names = spec.split()
    if not Path(file).is_file():
        raise ConfigError(f"--controllers {spec!r}: no such file {file!r}")
    owners = [m for m in models if m.gazebo.ros_control is not None]
    if len(owners) != 1:
        have = ", ".join(m.name for m in owners) or "none"
        raise ConfigError(
            f"--controllers {spec!r} needs exactly one model with a gazebo_ros_control plugin; have: {have}"
        )
    owner = owners[0]
    config = with_controllers(owner.gazebo.ros_control, Path(file).read_text(), file, names or None)
    gazebo = dataclasses.replace(owner.gazebo, ros_control=config)
    return [dataclasses.replace(m, gazebo=gazebo) if m is owner else m for m in models]
