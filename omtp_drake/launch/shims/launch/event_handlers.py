"""``OnProcessExit`` and ``OnProcessStart``: actions when a process the launch started ends or starts."""

from __future__ import annotations

from typing import Any


class OnProcessExit:
    def __init__(self, *, target_action: Any = None, on_exit: Any, **_: Any) -> None:
        self.target_action = target_action
        self.actions = on_exit


class OnProcessStart:
    def __init__(self, *, target_action: Any = None, on_start: Any, **_: Any) -> None:
        self.target_action = target_action
        self.actions = on_start


__all__ = ["OnProcessExit", "OnProcessStart"]
