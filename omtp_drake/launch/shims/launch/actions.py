"""The launch actions course and tutorial files use, visited as ``ros2 launch`` visits them."""

from __future__ import annotations

import shlex
from collections.abc import Callable, Iterable
from typing import Any

from launch.launch_context import (
    LaunchContext,
    LaunchDescriptionEntity,
    Started,
    caller_line,
    normalize,
    perform,
)


class Action(LaunchDescriptionEntity):
    """An action: skipped when its ``condition`` is false, else ``execute``d."""

    def __init__(self, *, condition: Any = None, **_: Any) -> None:
        self.condition = condition
        self.where = caller_line()

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        if self.condition is not None and not self.condition.evaluate(context):
            return None
        return self.execute(context)

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None


class DeclareLaunchArgument(Action):
    """An argument: its given value, else its default; neither is an error."""

    def __init__(
        self,
        name: str,
        *,
        default_value: Any = None,
        description: str = "",
        choices: Iterable[str] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.name = name
        self.default_value = None if default_value is None else normalize(default_value)
        self.description = description
        self.choices = None if choices is None else list(choices)

    def execute(self, context: LaunchContext) -> None:
        if self.name not in context.launch_configurations:
            if self.default_value is None:
                raise RuntimeError(f'Required launch argument "{self.name}" was not provided.')
            context.launch_configurations[self.name] = perform(context, self.default_value)
        value = context.launch_configurations[self.name]
        if self.choices is not None and value not in self.choices:
            raise RuntimeError(
                f'Argument "{self.name}" provided value "{value}" is not valid. '
                f"Valid options are: {self.choices}"
            )


class SetLaunchConfiguration(Action):
    def __init__(self, name: Any, value: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.name, self.value = normalize(name), normalize(value)

    def execute(self, context: LaunchContext) -> None:
        context.launch_configurations[perform(context, self.name)] = perform(context, self.value)


class _Scope(Action):
    """Pushes (``push``) or pops the launch configurations (a scoped group's bounds)."""

    def __init__(self, push: bool) -> None:
        super().__init__()
        self.push = push

    def execute(self, context: LaunchContext) -> None:
        if self.push:
            context.scopes.append(dict(context.launch_configurations))
        else:
            context.launch_configurations = context.scopes.pop()


class _InFile(Action):
    """Marks entering (``path``) or leaving (None) an included launch file."""

    def __init__(self, path: str | None) -> None:
        super().__init__()
        self.path = path

    def execute(self, context: LaunchContext) -> None:
        if self.path is None:
            context.files.pop()
        else:
            context.files.append(self.path)


class IncludeLaunchDescription(Action):
    """Another launch file's description, its arguments set as launch configurations
    (they stay set after it, as in ``ros2 launch``; a ``GroupAction`` scopes them)."""

    def __init__(
        self, launch_description_source: Any, *, launch_arguments: Any = None, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        self.launch_description_source = launch_description_source
        if isinstance(launch_arguments, dict):
            launch_arguments = launch_arguments.items()
        self.launch_arguments = [(k, v) for k, v in (launch_arguments or [])]

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        path, description = self.launch_description_source.get_launch_description(context)
        sets: list[LaunchDescriptionEntity] = [SetLaunchConfiguration(k, v) for k, v in self.launch_arguments]
        return [*sets, _InFile(path), description, _InFile(None)]


class GroupAction(Action):
    """Its actions, with the launch configurations scoped to them (``scoped=True``)."""

    def __init__(
        self,
        actions: Iterable[LaunchDescriptionEntity],
        *,
        scoped: bool = True,
        launch_configurations: Any = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self.actions = list(actions)
        self.scoped = scoped
        self.launch_configurations = dict(launch_configurations or {})

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        sets: list[LaunchDescriptionEntity] = [
            SetLaunchConfiguration(k, v) for k, v in self.launch_configurations.items()
        ]
        if not self.scoped:
            return [*sets, *self.actions]
        return [_Scope(True), *sets, *self.actions, _Scope(False)]


class ExecuteProcess(Action):
    """A process: its command line (``cmd``, each word a text or substitutions)."""

    def __init__(self, *, cmd: Iterable[Any], name: Any = None, shell: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.cmd = [normalize(word) for word in cmd]
        self.name = name
        self.shell = shell

    def execute(self, context: LaunchContext) -> None:
        words = [perform(context, word) for word in self.cmd]
        if self.shell:
            words = shlex.split(" ".join(words))
        context.started.append(Started(self, self.where, words))


class TimerAction(Action):
    """Its actions after ``period`` seconds (what starts is the same; the cell has no wait)."""

    def __init__(self, *, period: Any, actions: Iterable[LaunchDescriptionEntity], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.period = period
        self.actions = list(actions)

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        return self.actions


class RegisterEventHandler(Action):
    def __init__(self, event_handler: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.event_handler = event_handler

    def execute(self, context: LaunchContext) -> None:
        context.handlers.append(self.event_handler)


class LogInfo(Action):
    def __init__(self, *, msg: Any, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.msg = normalize(msg)


class OpaqueFunction(Action):
    """``function(context, *args, **kwargs)``: the entities it returns are visited."""

    def __init__(
        self, *, function: Callable[..., Any], args: Any = None, kwargs: Any = None, **rest: Any
    ) -> None:
        super().__init__(**rest)
        self.function, self.args, self.kwargs = function, list(args or []), dict(kwargs or {})

    def execute(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        return list(self.function(context, *self.args, **self.kwargs) or [])


__all__ = [
    "Action",
    "DeclareLaunchArgument",
    "ExecuteProcess",
    "GroupAction",
    "IncludeLaunchDescription",
    "LogInfo",
    "OpaqueFunction",
    "RegisterEventHandler",
    "SetLaunchConfiguration",
    "TimerAction",
]
