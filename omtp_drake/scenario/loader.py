"""Loading scenarios: the one place a file becomes a :class:`Scenario`.

A scenario says which world to build: robots, cameras, bins, parts, plant
settings and the seed. It is the analogue of a Gazebo world plus launch file,
and the one home of the cell's facts that may vary (poses, sizes, rates); the
fixed sizes of the cell's pieces live in their model files (``models/``).

Files are typed by Drake's YAML loader, the one checker of keys and types; a
document it refuses is one clear error naming the file, the key path and the
valid choices (:mod:`omtp_drake.scenario.refusals` finds them), and the values
are then checked by the configs' ``validate()``.

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

import copy
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml
from pydrake.common.yaml import yaml_load_typed
from pydrake.math import RollPitchYaw

from omtp_drake.errors import ConfigError, ScenarioError, UnknownNameError
from omtp_drake.scenario.camera import LogicalCameraConfig
from omtp_drake.scenario.configs import FrameConfig, PartConfig
from omtp_drake.scenario.models import ModelConfig
from omtp_drake.scenario.refusals import LOADER_ERRORS, refusal_message
from omtp_drake.scenario.robot_world import ROBOT_FILE_SUFFIXES, with_robot
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


class _Dumper(getattr(yaml, "CSafeDumper", yaml.SafeDumper)):  # type: ignore[misc]
    """YAML's safe dumper; LibYAML's emitter where PyYAML has it (the same
    documents, 4x faster: every scenario that is not memoized is dumped for Drake's
    loader, and a refused one once per piece asked about)."""


_Loader.add_multi_constructor("!", _construct_tagged)


def _represent_tagged(dumper: yaml.SafeDumper, data: _Tagged) -> yaml.Node:
    if isinstance(data.value, dict):
        return dumper.represent_mapping(data.tag, data.value)
    if isinstance(data.value, list):
        return dumper.represent_sequence(data.tag, data.value)
    return dumper.represent_scalar(data.tag, str(data.value))


_Dumper.add_representer(_Tagged, _represent_tagged)


#: What this process parsed and typed, by content: a file's mapping by its path and text, a
#: document's Scenario by its data. Both are pure-Python YAML (5-30 ms a scenario) and a process
#: loads the same few scenarios many times (each Cell, each command, a test file's cells); each
#: caller gets its own deep copy (0.3 ms). Errors are not kept: a bad file is refused each time.
_PARSED: dict[tuple[str, str], dict] = {}
_TYPED: dict[str, Scenario] = {}
#: How many of each are kept (the oldest goes first).
_KEPT = 64
_MEMO_LOCK = threading.Lock()
_MISSING = object()


def _kept(memo: dict, key: Any, make: Callable[[], Any]) -> Any:
    """A deep copy of ``memo[key]``, made by ``make()`` the first time."""
    with _MEMO_LOCK:
        value = memo.get(key, _MISSING)
    if value is _MISSING:
        value = make()
        with _MEMO_LOCK:
            while len(memo) >= _KEPT:
                del memo[next(iter(memo))]
            memo[key] = value
    return copy.deepcopy(value)


def _typed(raw: dict) -> Scenario:
    """Drake's typed load of the document ``raw``; kept by its ``repr`` (exact for plain
    YAML data, which is all a file gives) when it holds nothing else."""
    load = lambda: yaml_load_typed(schema=Scenario, data=scenario_text(raw), defaults=Scenario())  # noqa: E731
    return _kept(_TYPED, repr(raw), load) if _plain(raw) else load()


def _plain(value: Any) -> bool:
    """``value`` is YAML's plain data: mappings, lists, strings, numbers, booleans, nulls, tags."""
    if isinstance(value, dict):
        return all(isinstance(k, str) and _plain(v) for k, v in value.items())
    if isinstance(value, list):
        return all(_plain(v) for v in value)
    if isinstance(value, _Tagged):
        return _plain(value.value)
    return value is None or type(value) in (str, int, float, bool)


def _read_yaml(path: Path) -> dict:
    """The file's mapping; malformed YAML is one line with file, line and column."""
    try:
        text = path.read_text()
        raw = _kept(_PARSED, (str(path), text), lambda: yaml.load(text, Loader=_Loader))  # noqa: S506 (a SafeLoader)
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
    for an item of a ``base:`` and the file that changes it), and so is a name that is
    not a string (the merge looks items up by name)."""
    for key in _NAMED_LISTS:
        items = raw.get(key)
        if isinstance(items, _Tagged):
            items = items.value
        if not isinstance(items, list):
            continue
        for item in items:
            if isinstance(item, dict) and "name" in item and not isinstance(item["name"], str):
                raise ScenarioError(
                    f"{path}: {key}: name {item['name']!r} must be a string (a name like {key[:-1]}1)"
                )
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


def scenario_from_dict(
    raw: dict,
    *,
    source: str = "scenario",
    name: str = "",
    models: Sequence[ModelConfig] = (),
    frames: Sequence[FrameConfig] = (),
) -> Scenario:
    """A validated Scenario from plain data (a scenario file's mapping, bases
    already merged). ``source`` names it in error messages. ``models`` and ``frames``:
    entries typed already (a launch's loaded models, its links fixed to the world), copied
    in after ``raw``'s before the checks (not dumped to YAML and read back)."""
    if not isinstance(raw, dict):
        raise ScenarioError(f"{source}: a scenario must be a mapping of keys, got {type(raw).__name__}")
    try:
        scenario = _typed(raw)
    except LOADER_ERRORS as e:
        raise ScenarioError(refusal_message(raw, Scenario, source, e, scenario_text)) from None
    if not raw.get("name"):
        scenario.name = name
    scenario.base = ""
    scenario.models += copy.deepcopy(list(models))
    scenario.frames += copy.deepcopy(list(frames))
    _apply_poses(scenario, raw, source)
    scenario.validate()
    return scenario


_FIXED_ROTATIONS = (
    "!Rpy {deg: [roll, pitch, yaw]}, !AngleAxis {angle_deg: a, axis: [x, y, z]} or !Identity {}"
)


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
            if not item.pose.IsDeterministic():
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose must be a fixed pose; "
                    f"valid rotations: {_FIXED_ROTATIONS}"
                )
            X = item.pose.GetDeterministicValue()
            if item.pose.base_frame not in (None, "", "world", getattr(item, "parent", "world")):
                raise ScenarioError(
                    f"{source}: {key}[{item.name}].pose.base_frame {item.pose.base_frame!r} is not "
                    f"supported; valid: world" + (" or the camera's parent" if key == "cameras" else "")
                )
            item.xyz = [float(v) for v in X.translation()]
            item.rpy = [float(v) for v in RollPitchYaw(X.rotation()).vector()]
            item.pose = None


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
    as it is; a name or a path is loaded (and so validated) here. A robot's URDF, xacro
    or SDF file is that robot in Gazebo's empty world
    (:func:`~omtp_drake.scenario.robot_world.with_robot`): ``omtp-drake tf-echo
    robot.urdf.xacro world camera_link``."""
    if isinstance(scenario, Scenario):
        return scenario
    if str(scenario).endswith(ROBOT_FILE_SUFFIXES):
        return with_robot(None, scenario)
    return load_scenario(scenario)
