"""The ``launch`` and ``launch_ros`` API a course or tutorial ``*.launch.py`` uses, in house
(neither is on PyPI): descriptions of actions, which :mod:`omtp_drake.ros2.launch_py`
evaluates as ``ros2 launch`` would and maps to the cell. ``ament_index_python``'s
``get_package_share_directory`` finds the workspace's packages.

A launch file imports these under their ROS names (``from launch import LaunchDescription``,
``from launch_ros.actions import Node``...) while it is loaded and its
``generate_launch_description()`` runs: :func:`ros_modules` makes the modules.
"""

from __future__ import annotations

import types
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, Optional

#: A substitution's value in a context (the launch configurations set so far).
Context = dict[str, str]


class Substitution:
    """Something whose text is known only when the launch runs (``perform(context)``)."""

    def perform(self, context: Context) -> str:
        raise NotImplementedError


def perform(value: Any, context: Context) -> str:
    """The text of ``value``: a string, a substitution, or a list of them joined (launch's rule)."""
    if isinstance(value, Substitution):
        return value.perform(context)
    if isinstance(value, (list, tuple)):
        return "".join(perform(v, context) for v in value)
    return str(value)


@dataclass
class TextSubstitution(Substitution):
    text: str = ""

    def perform(self, context: Context) -> str:
        return self.text


@dataclass
class LaunchConfiguration(Substitution):
    """A launch argument's value (``name:=value``, a DeclareLaunchArgument's default)."""

    variable_name: Any
    default: Any = None

    def perform(self, context: Context) -> str:
        name = perform(self.variable_name, context)
        if name in context:
            return context[name]
        if self.default is not None:
            return perform(self.default, context)
        from omtp_drake.errors import ConfigError

        raise ConfigError(f"launch configuration '{name}' does not exist (give it as {name}:=VALUE)")


@dataclass
class PathJoinSubstitution(Substitution):
    substitutions: list

    def perform(self, context: Context) -> str:
        import os

        return os.path.join(*(perform(s, context) for s in self.substitutions))


@dataclass
class FindPackageShare(Substitution):
    package: Any

    def perform(self, context: Context) -> str:
        return share_directory(perform(self.package, context))


@dataclass
class Command(Substitution):
    """``Command(['xacro ', file])``: only xacro is run here (its output, the URDF text)."""

    command: Any

    def perform(self, context: Context) -> str:
        import shlex

        from omtp_drake.errors import NotSupportedError

        words = shlex.split(perform(self.command, context))
        if not words or not words[0].endswith("xacro"):
            raise NotSupportedError(f"Command({' '.join(words)!r}): only xacro commands run in a launch here")
        args = dict(w.split(":=", 1) for w in words[2:] if ":=" in w)
        return SHARE.expand_xacro(words[1], args)


@dataclass
class LaunchDescription:
    entities: list = field(default_factory=list)

    def add_action(self, action: Any) -> None:
        self.entities.append(action)


@dataclass
class DeclareLaunchArgument:
    name: str
    default_value: Any = None
    description: str = ""
    choices: Optional[list] = None


@dataclass
class PythonLaunchDescriptionSource:
    launch_file_path: Any


@dataclass
class IncludeLaunchDescription:
    launch_description_source: Any
    launch_arguments: Any = None


@dataclass
class Node:
    package: Any = None
    executable: Any = None
    name: Any = None
    namespace: Any = None
    parameters: list = field(default_factory=list)
    arguments: list = field(default_factory=list)
    remappings: list = field(default_factory=list)
    output: str = "log"
    extra: dict = field(default_factory=dict)


@dataclass
class ExecuteProcess:
    cmd: list = field(default_factory=list)
    output: str = "log"
    extra: dict = field(default_factory=dict)


@dataclass
class TimerAction:
    period: Any = 0.0
    actions: list = field(default_factory=list)


@dataclass
class GroupAction:
    actions: list = field(default_factory=list)
    extra: dict = field(default_factory=dict)


@dataclass
class OnProcessExit:
    target_action: Any = None
    on_exit: Any = None


@dataclass
class RegisterEventHandler:
    event_handler: Any = None


@dataclass
class ParameterValue(Substitution):
    value: Any
    value_type: Any = None

    def perform(self, context: Context) -> str:
        return perform(self.value, context)


class _Share:
    """Where ``get_package_share_directory`` looks: set while a launch runs."""

    def __init__(self) -> None:
        self.find: Callable[[str], str] = _no_workspace
        self.expand_xacro: Callable[[str, dict[str, str]], str] = _no_xacro


def _no_workspace(package: str) -> str:
    from omtp_drake.errors import ConfigError

    raise ConfigError(f"get_package_share_directory({package!r}) outside a launch")


def _no_xacro(path: str, args: dict[str, str]) -> str:
    return _no_workspace(path)


SHARE = _Share()


def share_directory(package: str) -> str:
    """``get_package_share_directory``: the package's folder in the launch's workspace."""
    return SHARE.find(package)


def _keyword_node(cls: type, known: Iterable[str]) -> Callable[..., Any]:
    """``cls`` taking any keywords: the known ones as fields, the rest in ``extra``."""

    def make(*args: Any, **kwargs: Any) -> Any:
        extra = {k: kwargs.pop(k) for k in list(kwargs) if k not in known}
        return cls(*args, **kwargs, extra=extra)

    return make


def ros_modules() -> dict[str, types.ModuleType]:
    """The modules ``launch``, ``launch_ros``, their submodules and ``ament_index_python``."""
    node_fields = (
        "package",
        "executable",
        "name",
        "namespace",
        "parameters",
        "arguments",
        "remappings",
        "output",
    )
    contents: dict[str, dict[str, Any]] = {
        "launch": {"LaunchDescription": LaunchDescription, "Substitution": Substitution},
        "launch.actions": {
            "DeclareLaunchArgument": DeclareLaunchArgument,
            "IncludeLaunchDescription": IncludeLaunchDescription,
            "ExecuteProcess": _keyword_node(ExecuteProcess, ("cmd", "output")),
            "TimerAction": TimerAction,
            "GroupAction": _keyword_node(GroupAction, ("actions",)),
            "RegisterEventHandler": RegisterEventHandler,
        },
        "launch.substitutions": {
            "LaunchConfiguration": LaunchConfiguration,
            "TextSubstitution": TextSubstitution,
            "PathJoinSubstitution": PathJoinSubstitution,
            "Command": Command,
        },
        "launch.launch_description_sources": {"PythonLaunchDescriptionSource": PythonLaunchDescriptionSource},
        "launch.event_handlers": {"OnProcessExit": OnProcessExit},
        "launch_ros": {},
        "launch_ros.actions": {"Node": _keyword_node(Node, node_fields)},
        "launch_ros.substitutions": {"FindPackageShare": FindPackageShare},
        "launch_ros.parameter_descriptions": {"ParameterValue": ParameterValue},
        "ament_index_python": {},
        "ament_index_python.packages": {"get_package_share_directory": share_directory},
    }
    modules = {}
    for name, names in contents.items():
        module = types.ModuleType(name, f"omtp_drake's stand-in of ROS 2's {name}")
        module.__dict__.update(names)
        modules[name] = module
    for name, module in modules.items():
        if "." in name:
            parent, child = name.rsplit(".", 1)
            setattr(modules[parent], child, module)
    return modules
