"""The object a ``with`` block makes current: the ROS session of a script, the FlexBE run of a
behaviour. ROS's client libraries are process-global; here each of those is current for one
block (blocks nest: the innermost is current) and a clear error names where it works outside one.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import Generic, TypeVar

from omtp_drake.errors import SimulationError

T = TypeVar("T")


class CurrentStack(Generic[T]):
    """The objects made current by nested :meth:`active` blocks; :meth:`current` is the innermost.

    Args:
        missing: the SimulationError's message when there is none (where it works).
    """

    def __init__(self, missing: str):
        self._missing = missing
        self._stack: list[T] = []

    def current(self) -> T:
        """The innermost current object (SimulationError outside every block)."""
        if not self._stack:
            raise SimulationError(self._missing)
        return self._stack[-1]

    @contextlib.contextmanager
    def active(self, item: T) -> Iterator[T]:
        """Makes ``item`` the current one for the ``with`` block."""
        self._stack.append(item)
        try:
            yield item
        finally:
            self._stack.remove(item)
