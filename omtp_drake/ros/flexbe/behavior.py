"""FlexBE's Behavior: a name, parameters, contained behaviours and ``create()``.

As in FlexBE, a behaviour's parameters are attributes set with
``add_parameter(name, default)`` in ``__init__``; ``set_parameter`` (``--param``)
casts a value to the default's type and reaches contained behaviours
(``add_behavior`` / ``use_behavior``) by a ``path/name`` or, without a path, every
behaviour that has the parameter. ``use_behavior`` builds the contained
behaviour's state machine (its input keys come from the parent, unless named in
``default_keys``).
"""

from __future__ import annotations

from typing import Any, Optional

import yaml

from omtp_drake.ros.flexbe.engine import Logger, OperatableStateMachine
from omtp_drake.ros.flexbe.userdata import UserData


class Behavior:
    """Subclass it, set ``self.name`` and implement ``create()`` returning the state machine."""

    def __init__(self) -> None:
        self._state_machine: Optional[OperatableStateMachine] = None
        self.name = "unnamed behavior"
        self.id = 0
        self.contains: dict[str, Behavior] = {}
        self._parameters: list[str] = []

    def create(self) -> Optional[OperatableStateMachine]:
        """The behaviour's state machine (called right before it runs)."""
        return None

    def add_parameter(self, name: str, default: Any) -> None:
        setattr(self, name, default)
        if name not in self._parameters:
            self._parameters.append(name)

    def add_behavior(self, behavior_class: type, behavior_id: str) -> None:
        self.contains[behavior_id] = behavior_class()

    def use_behavior(
        self,
        behavior_class: type,
        behavior_id: str,
        default_keys: Optional[list[str]] = None,
        parameters: Optional[dict[str, Any]] = None,
    ) -> Optional[OperatableStateMachine]:
        if behavior_id not in self.contains:
            Logger.logerr("Tried to use a behavior without adding it!")
            return None
        behavior = self.contains[behavior_id]
        for name, value in (parameters or {}).items():
            setattr(behavior, name, value)
        machine = behavior._get_state_machine()
        if default_keys:
            machine._input_keys = [k for k in machine._input_keys if k not in default_keys]
        for key in machine._input_keys:
            machine._own_userdata.remove(key)
        return machine

    def _get_state_machine(self) -> OperatableStateMachine:
        if self._state_machine is None:
            machine = self.create()
            if not isinstance(machine, OperatableStateMachine):
                got = type(machine).__name__
                raise TypeError(f"{type(self).__name__}.create() must return its state machine, got {got}")
            self._state_machine = machine
        return self._state_machine

    def prepare_for_execution(self, input_data: Optional[dict[str, Any]] = None) -> OperatableStateMachine:
        """Builds the state machine; ``input_data`` overrides its userdata defaults."""
        machine = self._get_state_machine()
        for key, value in (input_data or {}).items():
            if key in machine._own_userdata.keys():
                machine._own_userdata[key] = value
        return machine

    def get_contained_behaviors(self) -> dict[str, Behavior]:
        """``path -> behaviour`` of all contained behaviours, at any depth."""
        out: dict[str, Behavior] = {}
        for behavior_id, behavior in self.contains.items():
            out[f"/{behavior_id}"] = behavior
            out.update({f"/{behavior_id}{k}": v for k, v in behavior.get_contained_behaviors().items()})
        return out

    def set_parameter(self, name: str, value: Any) -> bool:
        """Sets parameter ``name`` (``path/name`` for a contained behaviour's); whether it existed."""
        path, _, key = name.rpartition("/")
        behaviors: dict[str, Behavior] = {"": self, **self.get_contained_behaviors()}
        path = "/" + path.strip("/") if path else ""
        found = False
        for behavior_path, behavior in behaviors.items():
            if behavior_path.startswith(path) and hasattr(behavior, key) and not key.startswith("_"):
                setattr(behavior, key, _typed(getattr(behavior, key), value))
                found = True
        return found

    def parameter_names(self) -> list[str]:
        return list(self._parameters)

    @property
    def userdata(self) -> UserData:
        return self._get_state_machine().userdata


def _typed(default: Any, value: Any) -> Any:
    """``value`` (a command-line string) as the type of the parameter's ``default``."""
    if not isinstance(value, str) or isinstance(default, str):
        return value
    if isinstance(default, bool):
        return value.strip().lower() not in ("0", "false", "no", "off", "")
    if isinstance(default, int):
        return int(value)
    if isinstance(default, float):
        return float(value)
    if isinstance(default, (dict, list)):
        return yaml.safe_load(value)
    return value
