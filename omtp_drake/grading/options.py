"""The ``ros-run`` options ``grade`` passes on: for the whole class, and per script.

:data:`ROS_RUN_OPTIONS` is the one table of them (option name -> ``ros-run``
flag and the check of its values). ``grade`` has a flag of the same name for
each, built from ros-run's (the class's value), and a class folder may hold
:data:`OVERRIDES_FILE` mapping a script's file name to its own values, e.g. a
class that mixes MoveIt versions::

    old_student.py:
      moveit: melodic
    lena.py:
      srdf: lena/omtp.srdf            # a path in grade.yaml is relative to the class folder
      call: [/spawn_object_at_robot2]
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from omtp_drake.errors import ConfigError, check_duration

#: The per-script overrides file of a class folder.
OVERRIDES_FILE = "grade.yaml"


@dataclass(frozen=True)
class RosRunOption:
    """One ros-run flag ``grade`` passes on: ``check(value, base)`` returns the value or
    raises ConfigError naming the valid ones (read where ros-run reads them); ``base``
    is the folder a relative path is relative to."""

    flag: str
    check: Callable[[Any, Path], Any]
    #: The flag may be given more than once (a list in grade.yaml).
    many: bool = False


def _moveit_version(value: Any, _base: Path) -> str:
    from omtp_drake.ros.run.bring_up import MOVEIT_VERSIONS

    if value not in MOVEIT_VERSIONS:
        raise ConfigError(f"{value!r} is unknown; valid: {', '.join(MOVEIT_VERSIONS)}")
    return str(value)


def _file(value: Any, base: Path) -> str:
    path = (base / str(value)).resolve()
    if not path.is_file():
        raise ConfigError(f"{str(value)!r}: no such file ({path})")
    return str(path)


def _folder(value: Any, base: Path) -> str:
    path = (base / str(value)).resolve()
    if not path.is_dir():
        raise ConfigError(f"{str(value)!r}: no such folder ({path})")
    return str(path)


def _seconds(value: Any, _base: Path) -> float:
    return check_duration("(simulated seconds)", value, zero=True)


def _latency(value: Any, _base: Path) -> str:
    from omtp_drake.ros.comm.latency import resolve_latency
    from omtp_drake.scenario.latency import RosLatencyConfig

    resolve_latency(RosLatencyConfig(), str(value))  # raises ConfigError naming the valid names
    return str(value)


def _call(value: Any, _base: Path) -> str:
    from omtp_drake.ros.run.setup_steps import parse_call

    parse_call(str(value))  # the service's name and its YAML arguments
    return str(value)


#: grade's name of an option -> the ros-run flag it becomes. ``grade``'s own flag copies
#: the ros-run flag's type, values and metavar from ros-run's parser.
ROS_RUN_OPTIONS: dict[str, RosRunOption] = {
    "moveit": RosRunOption("--moveit", _moveit_version),
    "srdf": RosRunOption("--srdf", _file),
    "moveit_config": RosRunOption("--moveit-config", _folder),
    "call": RosRunOption("--call", _call, many=True),
    "settle": RosRunOption("--settle", _seconds),
    "latency": RosRunOption("--latency", _latency),
    "settle_after": RosRunOption("--settle-after", _seconds),
}


def add_grade_flags(grade: argparse.ArgumentParser, ros_run: argparse.ArgumentParser) -> None:
    """A ``grade`` flag per entry of :data:`ROS_RUN_OPTIONS`, as ros-run's (default: not passed)."""
    actions = {flag: a for a in ros_run._actions for flag in a.option_strings}
    for name, option in ROS_RUN_OPTIONS.items():
        a = actions[option.flag]
        kwargs: dict[str, Any] = {"choices": a.choices, "metavar": a.metavar}
        if a.type is not None:
            kwargs["type"] = a.type
        grade.add_argument(
            option.flag,
            dest=f"ros_{name}",
            default=None,
            action="append" if option.many else "store",
            help=f"ros-run's {option.flag} for every script ({OVERRIDES_FILE} in DIR: per script)",
            **kwargs,
        )


def class_options(args: argparse.Namespace) -> dict[str, Any]:
    """The options given to ``grade`` on its command line."""
    values = {name: getattr(args, f"ros_{name}", None) for name in ROS_RUN_OPTIONS}
    return {k: v for k, v in values.items() if v is not None}


def check_options(options: Mapping[str, Any], where: str, base: Path) -> dict[str, Any]:
    """``options`` checked against the table (names, values; paths relative to ``base``)."""
    if not isinstance(options, Mapping):
        raise ConfigError(f"{where}: the options must be a mapping of name: value, got {options!r}")
    checked: dict[str, Any] = {}
    for name, value in options.items():
        if name not in ROS_RUN_OPTIONS:
            raise ConfigError(f"{where}: unknown option {name!r}; valid: {', '.join(ROS_RUN_OPTIONS)}")
        option = ROS_RUN_OPTIONS[name]
        values = value if option.many and isinstance(value, list) else [value]
        try:
            good = [option.check(v, base) for v in values]
        except ConfigError as e:
            raise ConfigError(f"{where}: {name} {e}") from None
        checked[str(name)] = good if option.many else good[0]
    return checked


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
    return {
        str(name): check_options(options or {}, f"{path}: {name}", folder) for name, options in raw.items()
    }


def ros_run_flags(options: Mapping[str, Any]) -> list[str]:
    """The ``ros-run`` command-line flags of ``options`` (a list: the flag once per value)."""
    flags = []
    for name, value in options.items():
        for v in value if isinstance(value, list) else [value]:
            flags += [ROS_RUN_OPTIONS[name].flag, str(v)]
    return flags


def script_options(
    script: str, class_values: Mapping[str, Any], overrides: Mapping[str, Mapping[str, Any]]
) -> dict[str, Any]:
    """The class's options with ``script``'s own on top."""
    return {**class_values, **overrides.get(script, {})}
