"""FlexBE's userdata: the data a state machine hands from state to state.

A state sees the container's userdata through a view (:class:`UserData` with a
reference, the state's input and output keys and the remapping of its
``add(...)``): reading a key the state did not declare as input is an error,
writing one it did not declare as output is an error, and an input-only value
the state changed in place is reported when it returns (FlexBE compares the
value's ``repr`` before and after). Written output keys go through the
remapping to the container's data; a container's own output keys go on to its
parent the same way.
"""

from __future__ import annotations

import copy
from typing import Any, Optional


class StateError(Exception):
    """A state did something its declaration does not allow (an unknown outcome...)."""


class StateMachineError(Exception):
    """A state machine is built wrongly (a missing transition target, a label twice...)."""


class UserDataError(Exception):
    """A state read or wrote a userdata key it did not declare."""


class UserData:
    """FlexBE's ``UserData``: keys as attributes or items, a view onto a reference."""

    def __init__(
        self,
        reference: Any = None,
        input_keys: Optional[list[str]] = None,
        output_keys: Optional[list[str]] = None,
        remap: Optional[dict[str, str]] = None,
    ):
        object.__setattr__(self, "_data", {})
        object.__setattr__(self, "_reference", reference if reference is not None else {})
        object.__setattr__(self, "_input_keys", input_keys)
        object.__setattr__(self, "_output_keys", output_keys)
        object.__setattr__(self, "_remap", dict(remap or {}))
        object.__setattr__(self, "_read_only", {})

    def __enter__(self) -> UserData:
        return self

    def __exit__(self, *exc: Any) -> None:
        for key, fingerprint in self._read_only.items():
            if repr(self._data[key]) != fingerprint:
                raise UserDataError(f"Illegally modified input-only key '{key}', declare it as output.")

    def _target(self, key: str) -> str:
        return self._remap.get(key, key)

    def __contains__(self, key: str) -> bool:
        if key in self._data:
            return True
        if self._input_keys is not None and key not in self._input_keys:
            return False
        return self._target(key) in self._reference

    def __getitem__(self, key: str) -> Any:
        if key in self._data:
            return self._data[key]
        if key not in self:
            if self._input_keys is not None and key not in self._input_keys:
                raise UserDataError(
                    f"Key '{key}' cannot be accessed, declare it as input key for read access."
                )
            raise UserDataError(f"No data found for key '{key}'")
        value = self._reference[self._target(key)]
        if self._output_keys is not None and key not in self._output_keys:
            self._data[key] = value
            self._read_only[key] = repr(value)
            if hasattr(value, "header"):
                value = copy.deepcopy(value)  # a stamped message: the state gets its own copy
        return value

    def __setitem__(self, key: str, value: Any) -> None:
        if self._output_keys is not None and key in self._output_keys:
            self._reference[self._target(key)] = value
        self._read_only.pop(key, None)
        self._data[key] = value

    def __getattr__(self, key: str) -> Any:
        if key.startswith("_"):
            raise AttributeError(key)
        return self[key]

    def __setattr__(self, key: str, value: Any) -> None:
        if key.startswith("_"):
            object.__setattr__(self, key, value)
            return
        if self._output_keys is not None and key not in self._output_keys:
            raise UserDataError(f"Key '{key}' cannot be set, declare it as output key for write access.")
        self[key] = value

    def add_from(self, other: UserData) -> None:
        """Adds ``other``'s own keys that this one does not have (a container's defaults)."""
        for key, value in other._data.items():
            self._data.setdefault(key, value)

    def remove(self, key: str) -> None:
        self._data.pop(key, None)

    def keys(self) -> list[str]:
        return list(self._data)

    def __len__(self) -> int:
        return len(self._data) + len(self._reference)

    def __repr__(self) -> str:
        return (
            f"UserData(data={self._data!r}, input_keys={self._input_keys!r}, "
            f"output_keys={self._output_keys!r}, remap={self._remap!r})"
        )
