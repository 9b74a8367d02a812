"""``IfCondition``, ``UnlessCondition`` and ``LaunchConfigurationEquals``/``NotEquals``."""

from __future__ import annotations

from typing import Any

from launch.launch_context import LaunchContext, normalize, perform


def _truth(text: str) -> bool:
    value = text.strip().lower()
    if value in ("true", "1"):
        return True
    if value in ("false", "0"):
        return False
    raise RuntimeError(f"condition {text!r} is not one of: true, 1, false, 0")


class IfCondition:
    def __init__(self, predicate_expression: Any) -> None:
        self.expression = normalize(predicate_expression)

    def evaluate(self, context: LaunchContext) -> bool:
        return _truth(perform(context, self.expression))


class UnlessCondition(IfCondition):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


class LaunchConfigurationEquals:
    def __init__(self, launch_configuration_name: str, expected_value: Any) -> None:
        self.name = launch_configuration_name
        self.expected = None if expected_value is None else normalize(expected_value)

    def evaluate(self, context: LaunchContext) -> bool:
        value = context.launch_configurations.get(self.name)
        return value == (None if self.expected is None else perform(context, self.expected))


class LaunchConfigurationNotEquals(LaunchConfigurationEquals):
    def evaluate(self, context: LaunchContext) -> bool:
        return not super().evaluate(context)


__all__ = ["IfCondition", "LaunchConfigurationEquals", "LaunchConfigurationNotEquals", "UnlessCondition"]
