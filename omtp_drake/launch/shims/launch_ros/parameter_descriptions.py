"""``ParameterValue`` and ``ParameterFile``."""

from __future__ import annotations

from typing import Any

import yaml
from launch.launch_context import LaunchContext, normalize, perform


class ParameterValue:
    """A parameter's value from substitutions: text with ``value_type=str``, else read as YAML."""

    def __init__(self, value: Any, *, value_type: Any = None) -> None:
        self.value = value
        self.value_type = value_type

    def evaluate(self, context: LaunchContext) -> Any:
        if not isinstance(self.value, (str, list, tuple)) and not hasattr(self.value, "perform"):
            return self.value
        text = perform(context, self.value)
        if self.value_type is str:
            return text
        return yaml.safe_load(text)


class ParameterFile:
    def __init__(self, param_file: Any, *, allow_substs: bool = False) -> None:
        self.param_file = normalize(param_file)

    def evaluate(self, context: LaunchContext) -> str:
        return perform(context, self.param_file)


__all__ = ["ParameterFile", "ParameterValue"]
