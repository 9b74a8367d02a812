"""The ``ros-run`` options ``grade`` passes on: for the whole class, and per script.

:data:`ROS_RUN_OPTIONS` is the one table of them (option name -> ``ros-run``
flag, its valid values and help). ``grade`` has a flag of the same name for
each (the class's value), and a class folder may hold :data:`OVERRIDES_FILE`
mapping a script's file name to its own values, e.g. a class that mixes
MoveIt versions::

    old_student.py:
      moveit: melodic
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from omtp_drake.errors import ConfigError

#: The per-script overrides file of a class folder.
OVERRIDES_FILE = "grade.yaml"

#: grade's name of an option -> the ros-run flag it becomes. Its values, type and help
#: are the ros-run flag's own (read from ros-run's parser): one entry per option passed on.
ROS_RUN_OPTIONS: dict[str, str] = {
    "moveit": "--moveit",
}


def _ros_run_actions(ros_run: argparse.ArgumentParser | None = None) -> dict[str, argparse.Action]:
    if ros_run is None:
        from omtp_drake.ros.cli import ros_run_parser

        ros_run = ros_run_parser()
    return {flag: a for a in ros_run._actions for flag in a.option_strings}


def add_grade_flags(grade: argparse.ArgumentParser, ros_run: argparse.ArgumentParser) -> None:
    """A ``grade`` flag per entry of :data:`ROS_RUN_OPTIONS`, as ros-run's (default: not passed)."""
    actions = _ros_run_actions(ros_run)
    for name, flag in ROS_RUN_OPTIONS.items():
        a = actions[flag]
        kwargs: dict[str, Any] = {"choices": a.choices, "metavar": a.metavar}
        if a.type is not None:
            kwargs["type"] = a.type
        grade.add_argument(
            flag,
            dest=f"ros_{name}",
            default=None,
            action="append" if isinstance(a, argparse._AppendAction) else "store",
            help=f"ros-run's {flag} for every script ({OVERRIDES_FILE} in DIR overrides it per script)",
            **kwargs,
        )


def class_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options given to ``grade`` on its command line."""
    values = {name: getattr(args, f"ros_{name}", None) for name in ROS_RUN_OPTIONS}
    return {k: v for k, v in values.items() if v is not None}


def check_options(options: Mapping[str, Any], where: str) -> dict[str, Any]:
    """``options`` checked against the table and ros-run's flags (names, values, types)."""
    if not isinstance(options, Mapping):
        raise ConfigError(f"{where}: the options must be a mapping of name: value, got {options!r}")
    actions = _ros_run_actions() if options else {}
    checked: dict[str, Any] = {}
    for name, value in options.items():
        if name not in ROS_RUN_OPTIONS:
            raise ConfigError(f"{where}: unknown option {name!r}; valid: {', '.join(ROS_RUN_OPTIONS)}")
        action = actions[ROS_RUN_OPTIONS[name]]
        many = isinstance(action, argparse._AppendAction)
        values = value if many and isinstance(value, list) else [value]
        checked[str(name)] = [_check_value(action, name, v, where) for v in values]
        if not many:
            checked[str(name)] = checked[str(name)][0]
    return checked


def _check_value(action: argparse.Action, name: str, value: Any, where: str) -> Any:
    if action.type is not None and callable(action.type):
        try:
            value = action.type(str(value))
        except (TypeError, ValueError):
            raise ConfigError(f"{where}: {name} {value!r} is not a valid value") from None
    if action.choices is not None and value not in action.choices:
        raise ConfigError(
            f"{where}: {name} {value!r} is unknown; valid: {', '.join(map(str, action.choices))}"
        )
    return value


def load_overrides(folder: Path, scripts: Sequence[Path]) -> dict[str, dict[str, Any]]:
    """Script file name -> its options, from ``folder/grade.yaml`` (empty when there is none)."""
    import yaml

    path = folder / OVERRIDES_FILE
    if not path.is_file():
        return {}
    try:
        raw = yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as e:
        raise ConfigError(f"{path}: not valid YAML ({e})") from None
    if not isinstance(raw, dict):
        raise ConfigError(f"{path}: must map script file names to options, got {type(raw).__name__}")
    names = [s.name for s in scripts]
    for name in raw:
        if name not in names:
            raise ConfigError(f"{path}: no script {name!r} in the folder; scripts: {', '.join(names)}")
    return {str(name): check_options(options or {}, f"{path}: {name}") for name, options in raw.items()}


def ros_run_flags(options: Mapping[str, Any]) -> list[str]:
    """The ``ros-run`` command-line flags of ``options`` (a list: the flag once per value)."""
    flags = []
    for name, value in options.items():
        for v in value if isinstance(value, list) else [value]:
            flags += [ROS_RUN_OPTIONS[name], str(v)]
    return flags


def script_options(
    script: str, class_values: Mapping[str, Any], overrides: Mapping[str, Mapping[str, Any]]
) -> dict[str, Any]:
    """The class's options with ``script``'s own on top."""
    return {**class_values, **overrides.get(script, {})}
