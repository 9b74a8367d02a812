"""A batch's plan: seeds and settings parsed and checked, every run built before any starts.

Settings are dotted paths into the :class:`~omtp_drake.scenario.Scenario`
dataclasses (``task.max_tool_speed``, ``spawner.yaw_variance``); a list of
named items is indexed by name (``cameras.logical_camera_2.position_noise_sigma``).
Each value goes through the scenario loader (:func:`scenario_from_dict`), so it
is checked like a value in a scenario file; every bad key, value or seed range
is one error before any cluster starts (:func:`plan_batch`).
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import itertools
import re
import typing
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy as np
import yaml

from omtp_drake.errors import ConfigError, OmtpError, check_duration

if TYPE_CHECKING:
    from omtp_drake.scenario import Scenario

#: Fields a sweep may not set: identity, and the seed (``seeds`` sets it).
_NOT_SWEEPABLE = ("name", "description", "base", "seed")


def parse_seeds(text: str) -> list[int]:
    """``START:STOP`` (START, ..., STOP - 1, as Python's range) or a comma list
    (``3,7,9``) of seeds >= 0. ConfigError for an empty or malformed range."""
    valid = "valid: START:STOP with integers 0 <= START < STOP (e.g. 0:100), or a list like 3,7,9"
    text = str(text).strip()
    try:
        if ":" in text:
            start_text, stop_text = text.split(":")
            start, stop = int(start_text), int(stop_text)
        else:
            seeds = [int(s) for s in text.split(",")]
    except ValueError:
        raise ConfigError(f"--seeds {text!r} is malformed; {valid}") from None
    if ":" in text:
        if start < 0 or stop <= start:
            raise ConfigError(f"--seeds {text!r} is an empty range; {valid}")
        return list(range(start, stop))
    return check_seeds(seeds)


def check_seeds(seeds: Iterable[int]) -> list[int]:
    """The seeds as a list: at least one, each an integer >= 0, none repeated."""
    out = list(seeds)
    if not out:
        raise ConfigError("seeds: the list of seeds is empty; valid: one or more integers >= 0")
    for seed in out:
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise ConfigError(f"seed {seed!r} is invalid; valid: integers >= 0")
    repeated = sorted({s for s in out if out.count(s) > 1})
    if repeated:
        raise ConfigError(f"seeds repeat: {', '.join(map(str, repeated))}; give each seed once")
    return [int(s) for s in out]


def parse_sets(items: Sequence[str]) -> dict[str, list[Any]]:
    """``--set key=v1,v2`` options as {key: [values]} (values parsed as YAML;
    commas inside ``[...]`` do not split)."""
    sweep: dict[str, list[Any]] = {}
    for item in items:
        key, sep, values_text = item.partition("=")
        key = key.strip()
        if not sep or not key or not values_text.strip():
            raise ConfigError(
                f"--set takes KEY=VALUE[,VALUE...] (e.g. task.max_tool_speed=0.6,0.8), got {item!r}"
            )
        if key in sweep:
            raise ConfigError(f"--set {key} is given twice; give its values once: {key}=V1,V2")
        sweep[key] = [_parse_value(key, text) for text in _split_values(values_text)]
    return sweep


def _split_values(text: str) -> list[str]:
    """``a,[1,2],b`` -> ``a``, ``[1,2]``, ``b``."""
    parts, depth, current = [], 0, ""
    for c in text:
        depth += c in "[{"
        depth -= c in "]}"
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    return parts + [current]


def _parse_value(key: str, text: str) -> Any:
    if not text.strip():
        raise ConfigError(f"--set {key}: an empty value; give values like {key}=0.5,1.0")
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise ConfigError(f"--set {key}={text}: not a YAML value ({str(e).splitlines()[0]})") from None
    if isinstance(value, dict) or value is None:
        raise ConfigError(f"--set {key}={text}: not a value; valid: a number, true/false, a string or a list")
    return value


def format_value(value: Any) -> str:
    """A setting's value as text (as it would be written in YAML)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(format_value(v) for v in value) + "]"
    return str(value)


def settings_label(settings: Mapping[str, Any]) -> str:
    """``task.max_tool_speed=0.6 spawner.yaw_variance=0``, or ``defaults``."""
    return " ".join(f"{k}={format_value(v)}" for k, v in settings.items()) or "defaults"


def _key_steps(raw: Mapping[str, Any], key: str, scenario: str) -> list[tuple[str, str]]:
    """The steps (``field`` name or list ``item`` name) of ``key`` into a
    scenario's plain data; ConfigError naming the valid keys or names."""
    from omtp_drake.scenario import Scenario, is_record, schema_fields

    words = key.split(".")
    if not all(words):
        raise ConfigError(f"--set {key}: malformed key; valid: dotted field names like task.max_tool_speed")
    schema: Any = Scenario
    node: Any = raw
    steps: list[tuple[str, str]] = []
    i = 0
    while True:
        word = words[i]
        ftype = _field_type(key, schema, word, ".".join(words[:i]) or "the scenario")
        steps.append(("field", word))
        prefix = ".".join(words[: i + 1])
        child = node.get(word) if isinstance(node, dict) else None
        i += 1
        item_type = typing.get_args(ftype)[0] if typing.get_origin(ftype) is list else None
        if item_type is not None and is_record(item_type):
            name = words[i] if i < len(words) else None
            node = _named_item(key, scenario, prefix, child, name)
            steps.append(("item", words[i]))
            schema = item_type
            i += 1
            if i == len(words):
                raise ConfigError(
                    f"--set {key}: names an item, not a value; valid keys under it: "
                    f"{', '.join(schema_fields(item_type))}"
                )
            continue
        if is_record(ftype):
            if child is None:
                raise ConfigError(f"--set {key}: scenario {scenario} has no {prefix} to change")
            if i == len(words):
                raise ConfigError(
                    f"--set {key}: names a group, not a value; valid keys under it: "
                    f"{', '.join(schema_fields(ftype))}"
                )
            node, schema = child, ftype
            continue
        if i != len(words):
            raise ConfigError(f"--set {key}: {prefix} is a value, not a group of keys")
        return steps


def _field_type(key: str, schema: Any, word: str, where: str) -> Any:
    """The type of field ``word`` of record ``schema`` (at ``where`` in ``key``);
    ConfigError naming the sweepable fields when it has none of that name."""
    from omtp_drake.scenario import Scenario, closest_name, schema_fields, unwrap_optional

    fields = [f for f in schema_fields(schema) if not (schema is Scenario and f in _NOT_SWEEPABLE)]
    if word not in fields:
        near = closest_name(word, fields)
        hint = f" (closest: {near})" if near else ""
        extra = "; set seeds with --seeds" if schema is Scenario and word == "seed" else ""
        raise ConfigError(
            f"--set {key}: unknown key {word!r} in {where}{hint}; valid keys: {', '.join(fields)}{extra}"
        )
    return unwrap_optional(schema_fields(schema)[word])


def _named_item(key: str, scenario: str, prefix: str, items: Any, name: Optional[str]) -> dict:
    """The item called ``name`` of the list of named records ``items`` (at ``prefix``
    in ``key``); ConfigError listing the names when ``name`` is missing or unknown."""
    from omtp_drake.scenario import closest_name

    names = [str(x.get("name")) for x in (items or []) if isinstance(x, dict)]
    if name is None:
        raise ConfigError(
            f"--set {key}: {prefix} is a list of named items; give {prefix}.NAME.FIELD; "
            f"names: {', '.join(names) or 'none'}"
        )
    if name not in names:
        near = closest_name(name, names)
        hint = f" (closest: {near})" if near else ""
        raise ConfigError(
            f"--set {key}: {scenario} has no {prefix} item {name!r}{hint}; "
            f"names: {', '.join(names) or 'none'}"
        )
    return next(x for x in (items or []) if x.get("name") == name)


def _with_value(raw: dict, steps: list[tuple[str, str]], value: Any) -> dict:
    """A deep copy of ``raw`` with the value at ``steps`` replaced."""
    out = copy.deepcopy(raw)
    node: Any = out
    for kind, name in steps[:-1]:
        node = node[name] if kind == "field" else next(x for x in node if x.get("name") == name)
    node[steps[-1][1]] = copy.deepcopy(value)
    return out


@dataclass(frozen=True)
class RunSpec:
    """One run of a batch: a seed and a setting (values by dotted key)."""

    seed: int
    settings: dict[str, Any]
    #: The prepared scenario of the run's setting (parts and settings applied)
    #: in Drake YAML, shared by the setting's runs: what a worker runs
    #: (pydrake's config classes do not pickle). Its seed is replaced by ``seed``.
    scenario_yaml: str

    def scenario(self) -> Scenario:
        """The run's scenario: setting, parts and seed applied, checked."""
        return dataclasses.replace(scenario_from_yaml(self.scenario_yaml), seed=self.seed)

    @property
    def run_id(self) -> str:
        """A file-name-safe name: ``seed7__task.max_tool_speed=0.6``."""
        text = f"seed{self.seed}" + "".join(f"__{k}={format_value(v)}" for k, v in self.settings.items())
        text = re.sub(r"[^A-Za-z0-9._=+-]", "_", text)
        if len(text) > 150:
            digest = hashlib.sha1(text.encode()).hexdigest()[:12]
            text = f"seed{self.seed}__{digest}"
        return text


@dataclass(frozen=True)
class BatchPlan:
    """Every run of a batch, checked (see :func:`plan_batch`)."""

    scenario: str
    runs: list[RunSpec]
    parts: Optional[int]
    duration: Optional[float]
    #: Identifies the base scenario and run options (for resuming).
    fingerprint: str


def plan_batch(
    scenario: Union[Scenario, str, Path],
    seeds: Union[str, Iterable[int]],
    *,
    settings: Optional[Mapping[str, Sequence[Any]]] = None,
    parts: Optional[int] = None,
    duration: Optional[float] = None,
) -> BatchPlan:
    """Every (setting, seed) run of a batch, each scenario built and checked.

    ``settings`` maps dotted keys to the values to sweep (the grid is every
    combination); ``seeds`` is a list or a ``START:STOP`` string. Raises
    ConfigError / ScenarioError / UnknownNameError for a bad scenario, key,
    value, combination, seed range, ``parts`` or ``duration``; has no side effects.
    """
    from pydrake.common.yaml import yaml_dump_typed

    from omtp_drake.scenario import as_scenario

    seed_list = parse_seeds(seeds) if isinstance(seeds, str) else check_seeds(seeds)
    base = as_scenario(scenario)
    base.required_task()
    if duration is not None:
        check_duration("--duration", duration)
    sweep = {str(k): list(v) for k, v in (settings or {}).items()}
    if parts is not None and "task.parts" in sweep:
        raise ConfigError("give the number of parts once: --parts or --set task.parts, not both")
    base_text = yaml_dump_typed(base)
    raw = yaml.safe_load(base_text)
    steps = {}
    for key, values in sweep.items():
        if not values:
            raise ConfigError(f"--set {key}: no values; give values like {key}=0.5,1.0")
        steps[key] = _key_steps(raw, key, base.name)
        texts = [format_value(v) for v in values]
        repeated = sorted({t for t in texts if texts.count(t) > 1})
        if repeated:
            raise ConfigError(f"--set {key}: value {repeated[0]} is given twice")
        for value in values:  # each value alone: its error names it
            _build(raw, {key: value}, steps, base.name, parts)
    runs: list[RunSpec] = []
    for combo in itertools.product(*sweep.values()):
        setting = dict(zip(sweep, combo))
        text = yaml_dump_typed(_build(raw, setting, steps, base.name, parts))
        runs += [RunSpec(seed=seed, settings=setting, scenario_yaml=text) for seed in seed_list]
    fingerprint = hashlib.sha1(f"{base_text}\nparts={parts}\nduration={duration}".encode()).hexdigest()
    return BatchPlan(scenario=base.name, runs=runs, parts=parts, duration=duration, fingerprint=fingerprint)


def _build(
    raw: dict, setting: Mapping[str, Any], steps: Mapping[str, list], name: str, parts: Optional[int]
) -> Scenario:
    """The scenario with ``setting`` applied, loaded and prepared (checked)."""
    from omtp_drake.scenario import scenario_from_dict
    from omtp_drake.tasks.run import prepare

    data = raw
    for key, value in setting.items():
        data = _with_value(data, steps[key], value)
    source = "--set " + ", ".join(f"{k}={format_value(v)}" for k, v in setting.items())
    try:
        return prepare(scenario_from_dict(data, source=source, name=name), parts=parts)
    except OmtpError as e:
        text = str(e)
        raise ConfigError(text if text.startswith(source) or not setting else f"{source}: {text}") from None


def scenario_from_yaml(text: str) -> Scenario:
    """A scenario from its Drake YAML (``RunSpec.scenario_yaml``), checked."""
    from pydrake.common.yaml import yaml_load_typed

    from omtp_drake.scenario import Scenario

    scenario = yaml_load_typed(schema=Scenario, data=text, defaults=Scenario())
    scenario.validate()
    return scenario
