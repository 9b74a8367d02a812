"""Property-based fuzzing (Hypothesis) of the scenario loader, the station build and the CLI:
any scenario document either loads (and builds), or is refused with an omtp_drake.errors
error; never another exception, never a traceback from the CLI.

Documents are made from the schema: a valid scenario with random fields replaced by
edge and bad values (NaN, inf, negative, huge, wrong types, unknown keys, wrong
nesting). bench/bench_fuzz.py runs many more examples.
"""

import copy
import dataclasses
import functools
import math
import os
import typing

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from pydrake.multibody.plant import MultibodyPlantConfig

from omtp_drake.errors import OmtpError
from omtp_drake.scenario import Scenario, scenario_document, scenario_from_dict, scenario_text
from omtp_drake.scenario.loader import DIAGRAMS_DIR

#: How many documents each property tries (bench/bench_fuzz.py raises it).
SCALE = float(os.environ.get("OMTP_FUZZ_SCALE", "1"))

#: Values that break things: non-finite, huge, negative, zero, wrong types, nesting.
BAD = st.sampled_from([
    math.nan, math.inf, -math.inf, -1.0, 0.0, 1e9, -1e9, 1e-12, 7, -3, True, "", "abc",
    [], [1.0], [1.0, 2.0], [math.nan, 0.0, 1.0], [0.0, 0.0, -5.0], [1e6, 0.0, 0.0], {},
    {"x": 1}, None, [[1.0, 2.0, 3.0]], "R9Nowhere", "object_1", "robot2",
])


@functools.cache  # get_type_hints is slow and asked for every mapping of every drawn document
def _fields(schema) -> dict:
    if dataclasses.is_dataclass(schema):
        hints = typing.get_type_hints(schema)
        return {f.name: hints[f.name] for f in dataclasses.fields(schema)}
    if schema is MultibodyPlantConfig:
        return {f.name: f.type for f in schema.__fields__}
    return {}


def _paths(doc, schema, prefix=()):
    """Every (path, field type) of ``doc`` that follows ``schema``."""
    out = []
    if isinstance(doc, dict):
        fields = _fields(schema)
        for key, value in doc.items():
            field_type = fields.get(key)
            out.append((prefix + (key,), field_type))
            if field_type is not None:
                inner = _unwrap(field_type)
                if typing.get_origin(inner) is list and isinstance(value, list):
                    (item,) = typing.get_args(inner)
                    for i, element in enumerate(value):
                        out.append((prefix + (key, i), item))
                        out += _paths(element, item, prefix + (key, i))
                else:
                    out += _paths(value, inner, prefix + (key,))
    return out


def _unwrap(field_type):
    if typing.get_origin(field_type) is typing.Union:
        args = [a for a in typing.get_args(field_type) if a is not type(None)]
        return args[0] if len(args) == 1 else field_type
    return field_type


def _set(doc, path, value):
    target = doc
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value


def _base_documents() -> list[dict]:
    """The shipped scenarios as plain documents (bases merged), to mutate."""
    return [scenario_document(path) for path in sorted(DIAGRAMS_DIR.glob("*.yaml"))]


BASES = _base_documents()


@st.composite
def documents(draw):
    """A shipped scenario with 1-2 random changes from BAD, an unknown key or a
    misplaced mapping."""
    doc = copy.deepcopy(draw(st.sampled_from(BASES)))
    for _ in range(draw(st.integers(1, 2))):
        paths = _paths(doc, Scenario)
        path, field_type = draw(st.sampled_from(paths))
        kind = draw(st.sampled_from(["edge"] * 6 + ["bad", "bad", "unknown", "nest", "drop"]))
        if kind == "edge":  # a value of the right type, at an edge
            _set(doc, path, draw(_edge(field_type, _get(doc, path))))
        elif kind == "bad":
            _set(doc, path, draw(BAD))
        elif kind == "unknown" and isinstance(_get(doc, path[:-1]), dict):
            _get(doc, path[:-1])[draw(st.sampled_from(["hfov", "robot", "xyzz", "Name"]))] = 1
        elif kind == "nest":
            _set(doc, path, {"value": _get(doc, path)})
        elif kind == "drop" and isinstance(_get(doc, path[:-1]), dict):
            _get(doc, path[:-1]).pop(path[-1], None)
    return doc


NUMBERS = st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.5, 1e-9, 1e6, -1e6, 0.3, 2.5, 1e-3])


def _edge(field_type, current):
    """An edge value of the field's own type (numbers, names, list lengths, flags)."""
    inner = _unwrap(field_type) if field_type is not None else type(current)
    if inner is float or isinstance(current, float):
        return NUMBERS
    if inner is int or (isinstance(current, int) and not isinstance(current, bool)):
        return st.sampled_from([0, -1, 1, 3, 1000, 10**9])
    if inner is bool or isinstance(current, bool):
        return st.booleans()
    if inner is str or isinstance(current, str):
        return st.sampled_from(["", "robot1", "robot2", "bin_1", "logical_camera_2", "Home", "x y",
                                "weld", "force", "point", "sap", "world", "object_1"])
    if isinstance(current, list):
        return st.lists(NUMBERS, min_size=0, max_size=4)
    return BAD


def _get(doc, path):
    for key in path:
        doc = doc[key]
    return doc


def _load(doc):
    """A scenario, or None when refused with an omtp_drake error."""
    try:
        return scenario_from_dict(doc, source="fuzz.yaml", name="fuzz")
    except OmtpError:
        return None


@settings(max_examples=int(300 * SCALE), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(documents())
def test_loader_loads_or_refuses_with_an_omtp_error(doc):
    scenario = _load(doc)
    if scenario is not None:
        assert isinstance(scenario, Scenario)
        # What loads is valid: its numbers are finite, its positions in the cell.
        scenario.validate()


@settings(max_examples=int(25 * SCALE), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(documents())
def test_what_loads_builds_and_runs_or_is_refused(doc):
    """A drawn document is refused by the loader with an omtp_drake error, or it loads,
    builds and runs to the time asked: a scenario that loads and then fails to build
    or run (with any error, ours included) fails the test."""
    from omtp_drake.sim.runtime import FactoryRuntime

    scenario = _load(doc)
    event("refused by the loader" if scenario is None else "loaded")
    if scenario is None:
        return
    runtime = FactoryRuntime(scenario)
    runtime.advance_to(0.05)
    assert runtime.time == pytest.approx(0.05)


@settings(max_examples=int(20 * SCALE), deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(documents(), st.sampled_from([
    ["camera", "{path}", "--camera", "logical_camera_2", "--time", "0.1"],
    ["tf-echo", "{path}", "world", "robot2_tool0", "--time", "0.1"],
    ["run", "{path}", "--duration", "0.2", "-q"],
]))
def test_cli_prints_one_line_errors_only(tmp_path_factory, doc, argv):
    from omtp_drake.cli import main

    path = tmp_path_factory.mktemp("fuzz") / "fuzz.yaml"
    path.write_text(scenario_text(doc))
    code = main([a.format(path=path) for a in argv])  # any other exception fails the test
    assert code in (0, 1, 2)


def _assert_refused(tmp_path, text, words):
    """Loading scenario ``text`` raises an omtp_drake error whose message has every word."""
    from omtp_drake.scenario import load_scenario

    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(OmtpError) as e:
        load_scenario(path)
    for word in words:
        assert word in str(e.value), str(e.value)


@pytest.mark.parametrize("text, words", [
    ("base: omtp_factory\nparts:\n  - {name: p, xyz: [.nan, 0, 1]}\n", ["parts[p].xyz[0]", "nan", "finite"]),
    ("base: omtp_factory\nparts:\n  - {name: p, xyz: [0, 0, -5]}\n", ["outside the cell", "z >= 0"]),
    (
        "base: omtp_factory\nparts:\n  - {name: p, xyz: [1000000, 0, 1]}\n",
        ["outside the cell", "|x|, |y| <= 10"],
    ),
    ("base: lecture6_assignment4\nspawner: {xyz: [-8.3, -1.23, .inf]}\n", ["spawner.xyz", "inf", "finite"]),
    ("base: omtp_factory\ngravity: [0, 0, .nan]\n", ["gravity", "nan"]),
    ("base: omtp_factory\nrobots:\n  - {name: robot1, xy: [.nan, 1.8]}\n", ["robots[robot1].xy", "nan"]),
])
def test_non_finite_and_out_of_cell_values_are_refused_at_load(tmp_path, text, words):
    _assert_refused(tmp_path, text, words)


@pytest.mark.parametrize("text, words", [
    ("base: omtp_factory\ncameras:\n  - {name: logical_camera_2, update_rate_hz: 1.0e+9}\n",
     ["logical_camera_2", "update_rate_hz must be in (0, 1000] Hz, got 1000000000.0"]),
    ("base: fill_bin\ntask: {diffik_rate_hz: 1.0e+6}\n", ["task.diffik_rate_hz must be in (0, 1000] Hz"]),
    ("base: omtp_factory\nrobots:\n  - {name: robot2, command_rate_hz: 1.0e+5}\n",
     ["robots[robot2].command_rate_hz must be in (0, 1000] Hz"]),
    ("base: omtp_factory\nplant_config: {time_step: 1.0e-9}\n",
     ["plant_config.time_step must be in [0.0001, 0.02] s", "1e-09"]),
    ("base: fill_bin\npart_pool: 100000\n", ["part_pool must be in [0, 100], got 100000"]),
    ("base: lecture6_assignment4\nspawner: {period: 1.0e-9}\n",
     ["spawner.period must be 0 (no automatic spawns) or >= 0.001 s"]),
    ("base: omtp_factory\nsuction: {check_rate_hz: 1.0e+6}\n", ["check_rate_hz", "[10, 1000] Hz"]),
    ("base: omtp_factory\ncameras:\n  - {name: logical_camera_2, rgbd: true, aspect_ratio: 0.001}\n",
     ["rgbd_width", "1 <= rgbd_width / aspect_ratio <= 4096"]),
])
def test_rates_steps_and_sizes_that_would_hang_or_exhaust_memory_are_refused(tmp_path, text, words):
    """Found by the fuzz test: a camera at 1e9 Hz, a 1 ns plant step or a spawner
    period, a pool of 1e5 parts, a 4096 x 4e6 RGB-D image loaded and then hung the
    build or the first advance (one used 6 GB before it was stopped)."""
    _assert_refused(tmp_path, text, words)


def test_malformed_yaml_is_one_line_with_file_line_and_column(tmp_path):
    from omtp_drake.errors import ScenarioError
    from omtp_drake.scenario import load_scenario

    path = tmp_path / "broken.yaml"
    path.write_text("base: omtp_factory\nconveyor:\n  power: [1, 2\n  stop_on_beam: true\n")
    with pytest.raises(ScenarioError) as e:
        load_scenario(path)
    message = str(e.value)
    assert "\n" not in message and f"{path}:4:" in message
