"""One Gazebo layer, two transports: each plugin's rules (rates, frames, encodings, the
scheduler) live in ``omtp_drake/gazebo/`` only; ``omtp_drake/ros2/`` and the ROS 1
shim's ``plugin_topics`` are transports (names, types, QoS), built on that layer.
Read from the source with ``ast``, as tests/test_layering.py reads imports."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "omtp_drake"
LAYER = PACKAGE / "gazebo"
#: The transports of the layer: every module of ros2/, and the shim's plugin topics, Gazebo API
#: and spawner.
ROS1_TRANSPORTS = [PACKAGE / f"ros/gazebo/{name}.py" for name in ("plugin_topics", "ros_api", "spawner")]
TRANSPORTS = sorted(PACKAGE.glob("ros2/*.py")) + ROS1_TRANSPORTS
#: A constant by its name is a plugin rule when it names a rate, period, encoding or frame.
RULE_NAME = re.compile(r"(RATE|_HZ$|PERIOD|ENCODING|FRAME)")
#: REP 118's encodings a plugin could write.
ENCODINGS = {"rgb8", "bgr8", "rgba8", "mono8", "mono16", "16UC1", "32FC1"}


def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text())


def _constants(tree: ast.Module) -> dict[str, object]:
    """Module-level ``NAME = literal`` (and annotated) assignments."""
    out: dict[str, object] = {}
    for node in tree.body:
        targets, value = [], None
        if isinstance(node, ast.Assign):
            targets, value = node.targets, node.value
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            targets, value = [node.target], node.value
        for target in targets:
            if isinstance(target, ast.Name):
                try:
                    out[target.id] = ast.literal_eval(value)
                except ValueError:
                    out[target.id] = None
    return out


def _strings(tree: ast.Module) -> set[str]:
    return {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}


def _classes(tree: ast.Module) -> set[str]:
    return {n.name for n in ast.walk(tree) if isinstance(n, ast.ClassDef)}


@pytest.mark.parametrize("path", TRANSPORTS, ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_a_transport_holds_no_plugin_rule(path):
    tree = _tree(path)
    rules = sorted(name for name in _constants(tree) if RULE_NAME.search(name))
    assert not rules, f"{path.name} defines plugin rules {rules}: they belong in omtp_drake/gazebo/"
    written = sorted(s for s in _strings(tree) if s in ENCODINGS or s.endswith("_optical_frame"))
    assert not written, f"{path.name} writes encodings or frames {written}: the plugin layer's"
    schedulers = _classes(tree) & {"Periodic", "Sampled", "PeriodicSource"}
    assert not schedulers, f"{path.name} defines its own scheduler {schedulers}"


def test_both_transports_are_built_on_the_layer():
    """Both take the plugins from ``gazebo_plugins`` (the ROS 1 shim through its one door
    to the core, ``ros/comm/_core.py``, which re-exports the layer's)."""
    from omtp_drake.gazebo import plugins
    from omtp_drake.ros.comm import _core

    assert _core.gazebo_plugins is plugins.gazebo_plugins
    for path in (PACKAGE / "ros2/bridge.py", PACKAGE / "ros/gazebo/plugin_topics.py"):
        names = {
            (n.module, a.name)
            for n in ast.walk(_tree(path))
            if isinstance(n, ast.ImportFrom)
            for a in n.names
        }
        doors = {
            ("omtp_drake.gazebo.plugins", "gazebo_plugins"),
            ("omtp_drake.ros.comm._core", "gazebo_plugins"),
        }
        assert names & doors, path


def test_no_plugin_rate_frame_or_encoding_is_written_twice():
    """Each rule constant of the layer has one home: no other module of the package
    defines a constant of that name or writes its string value."""
    layer = {p: _tree(p) for p in sorted(LAYER.glob("*.py"))}
    rules = {
        name: (path, value)
        for path, tree in layer.items()
        for name, value in _constants(tree).items()
        if RULE_NAME.search(name)
    }
    assert {
        "JOINT_STATE_RATE_HZ",
        "COLOR_ENCODING",
        "DEPTH_ENCODING",
        "OPTICAL_FRAME",
        "STATE_PERIOD",
    } <= set(rules)
    twice = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = _tree(path)
        constants, strings = _constants(tree), _strings(tree)
        for name, (home, value) in rules.items():
            if path == home:
                continue
            if name in constants:
                twice.append(f"{name} in {path.relative_to(PACKAGE)} and {home.relative_to(PACKAGE)}")
            if isinstance(value, str) and value in strings and (value in ENCODINGS or "{" in value):
                twice.append(f"{value!r} ({name}) in {path.relative_to(PACKAGE)}")
    assert not twice, "\n".join(twice)


def test_the_rule_reader_finds_a_rule():
    tree = ast.parse('FOO_RATE_HZ = 50.0\nX: str = "rgb8"\nclass Periodic: pass\n')
    assert RULE_NAME.search("FOO_RATE_HZ") and _constants(tree) == {"FOO_RATE_HZ": 50.0, "X": "rgb8"}
    assert "rgb8" in _strings(tree) and "Periodic" in _classes(tree)


#: The ROS 1 shim's modules that served the gripper, belt and beam before the layer did.
SHIM_MODULES = [PACKAGE / "ros/gazebo/sensor_topics.py", PACKAGE / "ros/gazebo/cell_services.py"]
#: What the course's gripper, belt and beam plugins name: their topics, services and frame.
COURSE_PLUGIN_NAMES = ("break_beam", "conveyor/control", "gripper")


def _code_strings(tree: ast.Module) -> set[str]:
    """The string constants of ``tree`` but its docstrings (and other bare string statements)."""
    bare = {id(n.value) for n in ast.walk(tree) if isinstance(n, ast.Expr)}
    return {
        n.value
        for n in ast.walk(tree)
        if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in bare
    }


@pytest.mark.parametrize("path", TRANSPORTS + SHIM_MODULES, ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_the_gripper_belt_and_beam_are_the_layers(path):
    """The course's vacuum gripper, conveyor and break beam: their names, frames, rates and
    limits are written in ``omtp_drake/gazebo/`` only (vacuum_gripper, conveyor,
    proximity_ray); a transport gives them types (and ROS 2 its ``std_msgs`` views' names,
    made from the layer's topic names), and the shim's own copies are gone."""
    from omtp_drake.gazebo import conveyor

    tree = _tree(path)
    names = {s for s in _code_strings(tree) if " " not in s}  # a topic, service or frame: no prose
    named = sorted(s for s in names if any(name in s for name in COURSE_PLUGIN_NAMES))
    assert not named, f"{path.name} names the plugins' topics or frames {named}: the layer's"
    numbers = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, float)}
    assert conveyor.MAX_POWER not in numbers, f"{path.name} writes the belt's power limit"
    assert not _classes(tree) & {"BreakBeamSource", "GripperStateSource"}
    assert "_gripper_services" not in {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}


#: What a Gazebo world plugin's rules use (the states' maths, world edits, the spawner's timing
#: and draws): attributes called on the cell or its models, and modules below the layer.
WORLD_RULE_CALLS = {"relative", "parts_in_world", "spawn_part", "remove_part", "rename_part", "every"}
WORLD_RULE_MODULES = {"omtp_drake.scenario.conveyor_spawner", "omtp_drake.sim.driver", "omtp_drake.sim.pool"}
#: Names and texts the rules write: the spawner's services and topic, Gazebo's status messages.
WORLD_RULE_TEXTS = re.compile(
    r"^/(start_spawn|stop_spawn|spawn_object_once|spawned_part)$"
    r"|^(SpawnModel|GetModelState|SetModelState|GetLinkState|DeleteModel): "
)


def _world_rules(tree: ast.Module) -> list[str]:
    calls = {
        n.func.attr
        for n in ast.walk(tree)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr in WORLD_RULE_CALLS
    }
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)} & WORLD_RULE_MODULES
    auto_spawn = {
        "auto_spawn" for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr == "auto_spawn"
    }
    texts = {s for s in _strings(tree) if WORLD_RULE_TEXTS.search(s)}
    return sorted(calls | modules | auto_spawn | texts)


@pytest.mark.parametrize("path", TRANSPORTS, ids=lambda p: p.relative_to(PACKAGE).as_posix())
def test_a_transport_holds_no_gazebo_world_rule(path):
    """Model and link states, Gazebo's model services and the spawner: their rules are the
    layer's (gazebo/model_states, world_services, spawn, spawner); a transport converts."""
    found = _world_rules(_tree(path))
    assert not found, f"{path.name} holds Gazebo world rules {found}: they belong in omtp_drake/gazebo/"


def test_the_world_rule_reader_finds_the_rules_in_the_layer():
    found = set()
    for name in ("model_states", "world_services", "spawn", "spawner", "world"):
        found |= set(_world_rules(_tree(LAYER / f"{name}.py")))
    assert {"relative", "every", "auto_spawn", "/stop_spawn", "omtp_drake.sim.driver"} <= found
    assert any(t.startswith("GetModelState: ") for t in found) and "/spawned_part" in found
