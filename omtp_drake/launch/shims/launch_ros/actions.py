"""``Node`` (a ROS 2 node the launch starts) and ``PushRosNamespace``."""

from __future__ import annotations

import os
from collections.abc import Iterable
from typing import Any

import yaml
from launch.actions import Action
from launch.launch_context import LaunchContext, Started, normalize, perform

from launch_ros.parameter_descriptions import ParameterFile, ParameterValue


def _value(context: LaunchContext, value: Any) -> Any:
    """A parameter value: substitutions performed (and read as YAML, as launch_ros does)."""
    if isinstance(value, ParameterValue):
        return value.evaluate(context)
    if isinstance(value, dict):
        return {str(k): _value(context, v) for k, v in value.items()}
    if hasattr(value, "perform") or (
        isinstance(value, (list, tuple)) and any(hasattr(v, "perform") for v in value)
    ):
        text = perform(context, value)
        try:
            return yaml.safe_load(text)
        except yaml.YAMLError:
            return text
    if isinstance(value, (list, tuple)):
        return [_value(context, v) for v in value]
    return value


class Node(Action):
    def __init__(
        self,
        *,
        executable: Any,
        package: Any = None,
        name: Any = None,
        namespace: Any = None,
        parameters: Iterable[Any] | None = None,
        remappings: Iterable[tuple[Any, Any]] | None = None,
        arguments: Iterable[Any] | None = None,
        ros_arguments: Iterable[Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.package, self.executable = normalize(package or ""), normalize(executable)
        self.node_name = None if name is None else normalize(name)
        self.node_namespace = None if namespace is None else normalize(namespace)
        self.parameters = list(parameters or [])
        self.remappings = list(remappings or [])
        self.arguments = [normalize(a) for a in arguments or []]

    def execute(self, context: LaunchContext) -> None:
        executable = perform(context, self.executable)
        base = context.launch_configurations.get("ros_namespace", "/")
        ns = perform(context, self.node_namespace) if self.node_namespace is not None else ""
        namespace = ns if ns.startswith("/") else f"{base.rstrip('/')}/{ns}".rstrip("/") or "/"
        name = perform(context, self.node_name) if self.node_name is not None else ""
        parameters: list = []
        for item in self.parameters:
            if isinstance(item, dict):
                parameters.append(_value(context, item))
            else:
                path = item.evaluate(context) if isinstance(item, ParameterFile) else perform(context, item)
                parameters.append(os.path.abspath(path))
        started = Started(
            self,
            self.where,
            [executable, *(perform(context, a) for a in self.arguments)],
            package=perform(context, self.package),
            executable=executable,
            name=name,
            namespace=namespace,
            parameters=parameters,
            remappings=[(perform(context, a), perform(context, b)) for a, b in self.remappings],
        )
        context.started.append(started)


class PushRosNamespace(Action):
    def __init__(self, namespace: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.namespace = normalize(namespace)

    def execute(self, context: LaunchContext) -> None:
        ns = perform(context, self.namespace)
        base = context.launch_configurations.get("ros_namespace", "/")
        full = ns if ns.startswith("/") else f"{base.rstrip('/')}/{ns}"
        context.launch_configurations["ros_namespace"] = full


__all__ = ["Node", "PushRosNamespace"]
