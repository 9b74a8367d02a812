"""Loading scenarios: the one place a file becomes a :class:`Scenario`.

A scenario says which world to build: robots, cameras, bins, parts, plant
settings and the seed. It is the analogue of a Gazebo world plus launch file,
and the one home of the cell's facts that may vary (poses, sizes, rates); the
fixed sizes of the cell's pieces live in their model files (``models/``).

Files are read with Drake's typed YAML loader after a check of every key and
value against the schema, so a misspelt key, a wrong type or a non-finite
number is one clear error naming the file, the key and the valid choices.

A scenario file may start from another one with ``base: <name or path>``: the
base is loaded first and the file's keys are merged into it. Mappings merge
key by key; lists of named items (``robots``, ``cameras``, ``bins``,
``parts``) merge item by item by ``name`` (an item of a new name is appended);
other lists and values replace the base's; ``null`` removes an optional item
(``spawner: null``), and the tag ``!replace`` replaces a list or mapping
wholesale (``robots: !replace [...]`` keeps only the robots listed).

Poses of parts and cameras may be written as ``xyz`` / ``rpy`` lists, or as
``pose`` in Drake's ``schema::Transform`` form where that reads better::

    pose: {translation: [-8.0, -2.2, 1.7], rotation: !Rpy {deg: [0, 90, 0]}}

Example::

    from omtp_drake.scenario import as_scenario, load_scenario
    scenario = load_scenario("omtp_factory")          # a name from diagrams/
    scenario = load_scenario("my_world.yaml")         # or a path
    scenario = as_scenario(name_or_scenario)          # entry points: a name, a path or a Scenario
"""

import dataclasses
import difflib
import typing
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import yaml
from pydrake.common.schema import Transform
from pydrake.common.yaml import yaml_load_typed
from pydrake.math import RollPitchYaw

from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError
from omtp_drake.scenario.camera import LogicalCameraConfig
from omtp_drake.scenario.configs import PartConfig
from omtp_drake.scenario.schema import Scenario

#: Folder of the scenario files shipped with the package.
DIAGRAMS_DIR = Path(__file__).resolve().parents[2] / "diagrams"


def scenario_names() -> list[str]:
    """Names of the scenarios shipped in ``diagrams/``."""
    return sorted(p.stem for p in DIAGRAMS_DIR.glob("*.yaml"))


def _resolve(name_or_path: str | Path) -> Path:
    text = str(name_or_path)
    if text.endswith((".yaml", ".yml")) or "/" in text or Path(text).is_file():
        path = Path(text)
        if not path.is_file():
            raise ScenarioError(
                f"scenario file {text!r} does not exist; scenario names: {', '.join(scenario_names())}"
            )
        return path
    path = DIAGRAMS_DIR / f"{text}.yaml"
    if not path.is_file():
        raise UnknownNameError("scenario", text, scenario_names(), closest=False)
    return path


@dataclass(frozen=True)
class _Tagged:
    """A YAML value with a tag (``!Rpy {deg: [...]}``), kept for Drake's loader."""

    tag: str
    value: Any


class _Loader(yaml.SafeLoader):
    pass


def _construct_tagged(loader: yaml.SafeLoader, suffix: str, node: yaml.Node) -> _Tagged:
    if isinstance(node, yaml.MappingNode):
        value: Any = loader.construct_mapping(node, deep=True)
    elif isinstance(node, yaml.SequenceNode):
        value = loader.construct_sequence(node, deep=True)
    else:
        value = loader.construct_scalar(node)
    return _Tagged("!" + suffix, value)


class _Dumper(yaml.SafeDumper):
    pass


_Loader.add_multi_constructor("!", _construct_tagged)


def _represent_tagged(dumper: yaml.SafeDumper, data: _Tagged) -> yaml.Node:
    if isinstance(data.value, dict):
        return dumper.represent_mapping(data.tag, data.value)
    if isinstance(data.value, list):
        return dumper.represent_sequence(data.tag, data.value)
    return dumper.represent_scalar(data.tag, str(data.value))


_Dumper.add_representer(_Tagged, _represent_tagged)


def _read_yaml(path: Path) -> dict:
    """The file's mapping; malformed YAML is one line with file, line and column."""
    try:
        raw = yaml.load(path.read_text(), Loader=_Loader)  # noqa: S506 (a SafeLoader)
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else str(path)
        problem = e.problem or e.context or "malformed YAML"
        raise ScenarioError(f"{where}: {problem}") from None
    except yaml.YAMLError as e:
        raise ScenarioError(f"{path}: malformed YAML ({str(e).splitlines()[0]})") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"{path}: cannot be read ({e})") from None
    if raw is None:
        raise ScenarioError(
            f"{path}: the file is empty; a scenario needs keys (start it with: base: omtp_factory)"
        )
    if not isinstance(raw, dict):
        raise ScenarioError(f"{path}: a scenario must be a mapping of keys, got {type(raw).__name__}")
    _check_unique_names(raw, path)
    return raw


def _check_unique_names(raw: dict, path: Path) -> None:
    """A name given twice in one list of one file is an error (merging by name is
    for an item of a ``base:`` and the file that changes it)."""
    for key in _NAMED_LISTS:
        items = raw.get(key)
        if isinstance(items, _Tagged):
            items = items.value
        if not isinstance(items, list):
            continue
        names = [x["name"] for x in items if isinstance(x, dict) and isinstance(x.get("name"), str)]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ScenarioError(
                f"{path}: {key}: name {repeated[0]!r} is given twice; names in a list must be unique"
            )


#: The lists that merge item by item by ``name`` (see module doc).
_NAMED_LISTS = ("robots", "cameras", "bins", "parts", "faults")


def _merge(base: Any, child: Any, key: str = "") -> Any:
    """``child`` merged into ``base`` (see the module doc for the rules)."""
    if isinstance(child, _Tagged) and child.tag == "!replace":
        return child.value
    if isinstance(base, dict) and isinstance(child, dict):
        merged = dict(base)
        for k, v in child.items():
            merged[k] = _merge(base[k], v, k) if k in base else v
        return merged
    if (
        key in _NAMED_LISTS
        and isinstance(base, list)
        and isinstance(child, list)
        and all(isinstance(x, dict) and "name" in x for x in base + child)
    ):
        merged_list = [dict(x) for x in base]
        index = {x["name"]: i for i, x in enumerate(merged_list)}
        for item in child:
            if item["name"] in index:
                i = index[item["name"]]
                merged_list[i] = _merge(merged_list[i], item)
            else:
                index[item["name"]] = len(merged_list)
                merged_list.append(item)
        return merged_list
    return child


def _raw_scenario(path: Path, seen: tuple[Path, ...]) -> tuple[dict, str]:
    """The file's mapping merged into its bases' (and the file's own description
    of ``name``)."""
    if path in seen:
        raise ScenarioError(f"scenario {path.name} includes itself through 'base'")
    raw = _read_yaml(path)
    base = raw.get("base")
    if base:
        if not isinstance(base, str):
            raise ScenarioError(f"{path.name}: base must be a scenario name or path, got {base!r}")
        if "/" in base or base.endswith((".yaml", ".yml")):
            base = str((path.parent / base).resolve())
        base_raw, _ = _raw_scenario(_resolve(base).resolve(), seen + (path,))
        raw = _merge(base_raw, {k: v for k, v in raw.items() if k != "base"})
    return raw, path.stem


def scenario_document(name_or_path: str | Path) -> dict:
    """A scenario file as plain data: its mapping with every ``base:`` merged in (what
    :func:`load_scenario` checks and types), e.g. to change and write back with
    :func:`scenario_text`."""
    raw, _ = _raw_scenario(_resolve(name_or_path).resolve(), ())
    raw.pop("base", None)
    return raw


def scenario_text(document: dict) -> str:
    """A scenario document as YAML text that loads back the same (tags such as
    ``!Rpy`` kept)."""
    return yaml.dump(document, Dumper=_Dumper, sort_keys=False)


def load_scenario(name_or_path: str | Path) -> Scenario:
    """Loads a scenario by name (from ``diagrams/``) or from a YAML file path.

    Raises:
        UnknownNameError: no scenario of that name (the message lists them), or
            a reference to a robot, camera or bin the scenario lacks.
        ScenarioError: missing file, malformed YAML, unknown key, bad type.
        ConfigError: a value no world can be built from.
    """
    path = _resolve(name_or_path).resolve()
    raw, stem = _raw_scenario(path, ())
    raw.pop("base", None)
    return scenario_from_dict(raw, source=path.name, name=stem)


def scenario_from_dict(raw: dict, *, source: str = "scenario", name: str = "") -> Scenario:
    """A validated Scenario from plain data (a scenario file's mapping, bases
    already merged). ``source`` names it in error messages."""
    if not isinstance(raw, dict):
        raise ScenarioError(f"{source}: a scenario must be a mapping of keys, got {type(raw).__name__}")
    _check_schema(raw, Scenario, source, "")
    text = yaml.dump(raw, Dumper=_Dumper, sort_keys=False)
    try:
        scenario = yaml_load_typed(schema=Scenario, data=text, defaults=Scenario())
    except (RuntimeError, AssertionError, TypeError, ValueError) as e:
        # What the schema check above let through (Drake's own checks).
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise ScenarioError(f"{source}: bad value or type: {first}") from None
    if not raw.get("name"):
        scenario.name = name
    scenario.base = ""
    _apply_poses(scenario, raw, source)
    scenario.validate()
    return scenario


def _apply_poses(scenario: Scenario, raw: dict, source: str) -> None:
    """Turns each ``pose`` (schema::Transform) into the item's ``xyz`` / ``rpy``."""
    posed: tuple[tuple[str, Sequence[PartConfig | LogicalCameraConfig]], ...] = (
        ("parts", scenario.parts),
        ("cameras", scenario.cameras),
    )
    for key, items in posed:
        raw_items = raw.get(key) or []
        for item, raw_item in zip(items, raw_items):
            if item.pose is None:
                continue
            both = [k for k in ("xyz", "rpy") if k in raw_item]
            if both:
                raise ScenarioError(
                    f"{source}: {key}[{item.name}] gives both pose and {' and '.join(both)}; give one of them"
                )
            try:
                X = item.pose.GetDeterministicValue()
            except (RuntimeError, ValueError) as e:
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose must be a fixed pose: {str(e).splitlines()[0]}"
                ) from None
            if item.pose.base_frame not in (None, "", "world", getattr(item, "parent", "world")):
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose.base_frame {item.pose.base_frame!r} is not "
                    f"supported; valid: world" + (" or the camera's parent" if key == "cameras" else "")
                )
            item.xyz = [float(v) for v in X.translation()]
            item.rpy = [float(v) for v in RollPitchYaw(X.rotation()).vector()]
            item.pose = None


def schema_fields(schema: Any) -> dict[str, Any]:
    """Field name -> type of a dataclass or a pydrake config class (of the
    scenario's schema); empty for any other type."""
    if dataclasses.is_dataclass(schema):
        hints = typing.get_type_hints(schema)
        return {f.name: hints[f.name] for f in dataclasses.fields(schema)}
    return {f.name: f.type for f in getattr(schema, "__fields__", ())}


def is_record(schema: Any) -> bool:
    """Is ``schema`` a group of keys (a dataclass or config class, not a pose)?"""
    return (dataclasses.is_dataclass(schema) or hasattr(schema, "__fields__")) and schema is not Transform


def _check_schema(value: Any, schema: Any, source: str, path: str) -> None:
    """Raises ScenarioError for an unknown key or a value of the wrong type at ``path``."""
    where = f"{source}: {path}" if path else source
    origin = typing.get_origin(schema)
    if origin is typing.Union:
        options = [a for a in typing.get_args(schema) if a is not type(None)]
        if value is None:
            return
        schema = options[0] if len(options) == 1 else schema
        if len(options) != 1:
            return  # a variant (Drake checks it)
        origin = typing.get_origin(schema)
    if schema is Transform:
        if not isinstance(value, dict):
            raise ScenarioError(f"{where} must be a pose mapping (translation, rotation), got {value!r}")
        unknown = sorted(set(value) - {"base_frame", "translation", "rotation"})
        if unknown:
            raise ScenarioError(
                _unknown_key_message(where, unknown[0], ["base_frame", "translation", "rotation"])
            )
        _check_pose(value, where)
        return
    if is_record(schema):
        if not isinstance(value, dict):
            raise ScenarioError(
                f"{where} must be a mapping of keys ({', '.join(schema_fields(schema))}), got {value!r}"
            )
        fields = schema_fields(schema)
        for key, item in value.items():
            if key not in fields:
                raise ScenarioError(_unknown_key_message(where, str(key), list(fields)))
            _check_schema(item, fields[key], source, f"{path}.{key}" if path else str(key))
        return
    if origin is list:
        (item_schema,) = typing.get_args(schema)
        if not isinstance(value, list):
            raise ScenarioError(f"{where} must be a list, got {value!r}")
        for i, item in enumerate(value):
            label = item.get("name", i) if isinstance(item, dict) else i
            _check_schema(item, item_schema, source, f"{path}[{label}]")
        return
    expected = {float: "a number", int: "an integer", bool: "true or false", str: "a string"}
    if schema in expected:
        ok = {
            float: isinstance(value, (int, float)) and not isinstance(value, bool),
            int: isinstance(value, int) and not isinstance(value, bool),
            bool: isinstance(value, bool),
            str: isinstance(value, str),
        }[schema]
        if not ok:
            raise ScenarioError(f"{where} must be {expected[schema]}, got {value!r}")


def closest_name(name: str, valid: Sequence[str]) -> Optional[str]:
    """The valid name ``name`` was most likely meant to be: a close spelling, or
    one that holds its letters in order (an abbreviation: ``hfov`` for
    ``horizontal_fov``); None when nothing is close."""
    near = difflib.get_close_matches(name, list(valid), n=1, cutoff=0.5)
    if near:
        return near[0]

    def holds(word: str) -> bool:
        letters = iter(word)
        return all(c in letters for c in name)

    abbreviations = sorted((v for v in valid if holds(v)), key=len)
    return abbreviations[0] if abbreviations and len(name) >= 2 else None


_ROTATIONS = "!Rpy {deg: [roll, pitch, yaw]}, !AngleAxis {angle_deg: a, axis: [x, y, z]} or !Identity {}"


def _check_pose(value: dict, where: str) -> None:
    """A fixed pose: translation 3 numbers; rotation one of the fixed forms."""

    def numbers(x: Any, n: int) -> bool:
        return (
            isinstance(x, list)
            and len(x) == n
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in x)
        )

    if "translation" in value and not numbers(value["translation"], 3):
        raise ScenarioError(f"{where}.translation must be 3 numbers, got {value['translation']!r}")
    if "base_frame" in value and not isinstance(value["base_frame"], (str, type(None))):
        raise ScenarioError(f"{where}.base_frame must be a frame name, got {value['base_frame']!r}")
    if "rotation" not in value:
        return
    rotation = value["rotation"]
    forms = {"!Rpy": {"deg": 3}, "!AngleAxis": {"angle_deg": 1, "axis": 3}, "!Identity": {}}
    body = rotation.value if isinstance(rotation, _Tagged) else None
    if (
        not isinstance(rotation, _Tagged)
        or rotation.tag not in forms
        or not isinstance(body, dict)
        or set(body) != set(forms[rotation.tag])
        or not all(numbers(body[k] if n > 1 else [body[k]], n) for k, n in forms[rotation.tag].items())
    ):
        raise ScenarioError(f"{where}.rotation must be {_ROTATIONS}, got {_show(rotation)}")


def _show(value: Any) -> str:
    return f"{value.tag} {value.value!r}" if isinstance(value, _Tagged) else repr(value)


def _unknown_key_message(where: str, key: str, valid: list[str]) -> str:
    near = closest_name(key, valid)
    hint = f" (did you mean {near!r}?)" if near else ""
    return f"{where}: unknown key {key!r}{hint}; valid keys: {', '.join(valid)}"


def require_scenario(value: Any, who: str) -> Scenario:
    """``value`` if it is a :class:`Scenario`: the builders inside the package
    (``who``) take one; a name or path is loaded at the entry points (:func:`as_scenario`)."""
    if not isinstance(value, Scenario):
        raise ConfigError(
            f"{who} takes a Scenario, got {type(value).__name__} {value!r}; "
            f"load one first: {who}(load_scenario(name_or_path), ...)"
        )
    return value


def as_scenario(scenario: "Scenario | str | Path") -> Scenario:
    """The one door of the public entry points (``Cell``, ``FactoryRuntime``,
    ``run_task``, ``run_batch``, the CLI): a :class:`Scenario` is passed through
    as it is; a name or a path is loaded (and so validated) here."""
    if isinstance(scenario, Scenario):
        return scenario
    return load_scenario(scenario)
