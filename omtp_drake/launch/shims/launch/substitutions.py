"""The substitutions course and tutorial files use."""

from __future__ import annotations

import math
import os
import shlex
import shutil
from collections.abc import Iterable
from typing import Any

from launch.launch_context import LaunchContext, Substitution, TextSubstitution, normalize, perform


class LaunchConfiguration(Substitution):
    """A launch configuration's value (an argument's), else ``default``; else an error."""

    def __init__(self, variable_name: Any, *, default: Any = None) -> None:
        self.variable_name = normalize(variable_name)
        self.default = None if default is None else normalize(default)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.variable_name)
        if name in context.launch_configurations:
            return context.launch_configurations[name]
        if self.default is not None:
            return perform(context, self.default)
        raise RuntimeError(f"launch configuration '{name}' does not exist")


class Command(Substitution):
    """The output of a command (the reader runs xacro only)."""

    def __init__(self, command: Any, *, on_stderr: str = "fail") -> None:
        self.command = normalize(command)

    def perform(self, context: LaunchContext) -> str:
        text = perform(context, self.command)
        assert context.run_command is not None
        return context.run_command(shlex.split(text), text)


class PathJoinSubstitution(Substitution):
    def __init__(self, substitutions: Iterable[Any]) -> None:
        self.parts = [normalize(part) for part in substitutions]

    def perform(self, context: LaunchContext) -> str:
        return os.path.join(*(perform(context, part) for part in self.parts))


class FindExecutable(Substitution):
    def __init__(self, *, name: Any) -> None:
        self.name = normalize(name)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        return shutil.which(name) or name


class EnvironmentVariable(Substitution):
    def __init__(self, name: Any, *, default_value: Any = None) -> None:
        self.name = normalize(name)
        self.default_value = None if default_value is None else normalize(default_value)

    def perform(self, context: LaunchContext) -> str:
        name = perform(context, self.name)
        if name in os.environ:
            return os.environ[name]
        if self.default_value is None:
            raise RuntimeError(f"environment variable '{name}' does not exist")
        return perform(context, self.default_value)


class PythonExpression(Substitution):
    """A Python expression's value (``math``'s names in scope), as text."""

    def __init__(self, expression: Any) -> None:
        self.expression = normalize(expression)

    def perform(self, context: LaunchContext) -> str:
        names = {k: getattr(math, k) for k in dir(math) if not k.startswith("_")}
        return str(eval(perform(context, self.expression), {"__builtins__": {}}, names))


class ThisLaunchFileDir(Substitution):
    def perform(self, context: LaunchContext) -> str:
        return os.path.dirname(context.files[-1])


__all__ = [
    "Command",
    "EnvironmentVariable",
    "FindExecutable",
    "LaunchConfiguration",
    "PathJoinSubstitution",
    "PythonExpression",
    "Substitution",
    "TextSubstitution",
    "ThisLaunchFileDir",
]
