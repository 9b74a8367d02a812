"""The context a launch is visited in, the entity and substitution bases, and the visit."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

_HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def caller_line() -> str:
    """``file:line`` of the launch-file line that made the entity being built."""
    frame = sys._getframe(1)
    while frame is not None and frame.f_code.co_filename.startswith(_HERE):
        frame = frame.f_back  # type: ignore[assignment]
    return f"{frame.f_code.co_filename}:{frame.f_lineno}" if frame is not None else "?"


class Substitution:
    """A text known only when the launch is visited (``perform``)."""

    def perform(self, context: LaunchContext) -> str:
        raise NotImplementedError

    def __add__(self, other: Any) -> list:
        return [self, other]

    def __radd__(self, other: Any) -> list:
        return [other, self]


class TextSubstitution(Substitution):
    def __init__(self, *, text: str = "") -> None:
        self.text = str(text)

    def perform(self, context: LaunchContext) -> str:
        return self.text


def normalize(value: Any) -> list[Substitution]:
    """A text, a substitution or a list of them, as a list of substitutions."""
    if isinstance(value, Substitution):
        return [value]
    if isinstance(value, (str, os.PathLike, int, float)):
        return [TextSubstitution(text=os.fspath(value) if isinstance(value, os.PathLike) else str(value))]
    if isinstance(value, Iterable):
        return [s for item in value for s in normalize(item)]
    raise TypeError(f"a substitution must be a text or a Substitution, got {type(value).__name__}")


def perform(context: LaunchContext, value: Any) -> str:
    """The text of ``value`` (a text, a substitution or a list of them) in ``context``."""
    return "".join(s.perform(context) for s in normalize(value))


class LaunchDescriptionEntity:
    """Something a launch description holds: ``visit`` gives the entities it brings in."""

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity] | None:
        return None


@dataclass
class Started:
    """A process the launch starts: a ``Node`` (``package`` set) or an ``ExecuteProcess``."""

    action: Any
    where: str
    cmd: list[str]
    package: str = ""
    executable: str = ""
    name: str = ""
    namespace: str = "/"
    parameters: list = field(default_factory=list)
    remappings: list[tuple[str, str]] = field(default_factory=list)


@dataclass
class LaunchContext:
    """What a visit knows: the launch configurations (arguments), what starts, the event
    handlers registered, and the reader's hooks (``load_file``: a launch file's
    description; ``run_command``: a ``Command`` substitution's output)."""

    launch_configurations: dict[str, str] = field(default_factory=dict)
    started: list[Started] = field(default_factory=list)
    handlers: list[Any] = field(default_factory=list)
    files: list[str] = field(default_factory=list)
    scopes: list[dict[str, str]] = field(default_factory=list)
    load_file: Callable[[str], Any] | None = None
    run_command: Callable[[list[str], str], str] | None = None

    def visit(self, entity: LaunchDescriptionEntity) -> None:
        """Visits ``entity`` and what it brings in, depth first, in order (as the launch service)."""
        for child in entity.visit(self) or ():
            self.visit(child)
