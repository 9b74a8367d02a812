"""``grade --flexbe``: a class's FlexBE behaviours, one student workspace each.

The class folder holds one folder per student: a catkin ``src`` folder (its
packages found by their ``package.xml``) with one behaviour manifest. Each is
graded as a script is (:mod:`omtp_drake.grading.grade`): on its own copy, isolated,
with ``flexbe-run`` instead of ``ros-run``. Workspaces every student uses (the
course's states, ``generic_flexbe_states``) are given once with ``--workspace``.
"""

from __future__ import annotations

import shutil
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from omtp_drake.errors import ConfigError

#: The grade options flexbe-run takes (see omtp_drake.grading.options).
FLEXBE_OPTIONS = ("srdf", "moveit_config")


@dataclass(frozen=True)
class FlexbeGrading:
    """What a FlexBE grade adds to every run: the shared workspaces, Python 2 loading, and
    the behaviour to run where a workspace has several (its manifest name)."""

    workspaces: tuple[str, ...] = ()
    python2: bool = False
    behavior: str = ""


def find_workspaces(folder: str | Path, behavior: str = "") -> list[Path]:
    """The student workspaces of ``folder`` (its sub-folders, ``_`` and ``.`` ones left
    out), each checked to hold its behaviour (see :func:`behaviour_of`)."""
    path = Path(folder)
    if not path.is_dir():
        raise ConfigError(f"grade --flexbe needs a folder of student workspaces, got {str(folder)!r}")
    spaces = sorted(p for p in path.iterdir() if p.is_dir() and not p.name.startswith(("_", ".")))
    if not spaces:
        raise ConfigError(f"{str(folder)!r} has no workspace folders (one per student)")
    for space in spaces:
        behaviour_of(space, behavior)
    return spaces


def behaviour_of(workspace: Path, behavior: str = "") -> Any:
    """The behaviour of ``workspace`` to run (a ``BehaviorEntry``): its only one, or the one
    named ``behavior`` (blanks ignored, as flexbe-run matches names); one error naming
    what the workspace has otherwise."""
    from omtp_drake.ros.flexbe.workspace import Workspaces

    found = Workspaces([workspace]).behaviors()
    if behavior:
        found = [b for b in found if b.name.replace(" ", "") == behavior.replace(" ", "")] or found
    if len(found) != 1 or (behavior and found[0].name.replace(" ", "") != behavior.replace(" ", "")):
        names = ", ".join(repr(b.name) for b in found) or "none"
        hint = f" (none is {behavior!r})" if behavior else "; choose one with grade --behavior NAME"
        raise ConfigError(
            f"workspace {workspace.name!r} must hold one behaviour manifest to grade; it has {names}{hint}"
        )
    return found[0]


def check_flexbe_options(options: Mapping[str, Any], where: str) -> None:
    """Raises for an option flexbe-run does not take (``--moveit``, ``--call``...)."""
    for name in options:
        if name not in FLEXBE_OPTIONS:
            raise ConfigError(
                f"{where}: {name!r} is a ros-run option; flexbe-run takes {', '.join(FLEXBE_OPTIONS)}"
            )


def prepare(workspace: Path, work: Path, behavior: str = "") -> tuple[Path, list[str]]:
    """``workspace`` copied into ``work``; (the copied behaviour's source, the
    ``flexbe-run`` arguments before the common ones)."""
    copy = work / workspace.name
    shutil.copytree(workspace, copy, symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
    entry = behaviour_of(copy, behavior)
    return Path(entry.source), ["flexbe-run", entry.name, "--workspace", str(copy)]


def flexbe_flags(grading: FlexbeGrading) -> list[str]:
    """The shared workspaces and ``--python2`` as flexbe-run flags."""
    flags: list[str] = []
    for space in grading.workspaces:
        flags += ["--workspace", space]
    return flags + (["--python2"] if grading.python2 else [])


def shared_workspaces(folders: Sequence[str]) -> tuple[str, ...]:
    """``--workspace`` folders as absolute paths, each checked to exist."""
    out = []
    for folder in folders:
        path = Path(folder).resolve()
        if not path.is_dir():
            raise ConfigError(f"--workspace {folder!r}: no such folder")
        out.append(str(path))
    return tuple(out)
