"""The package's shape: layers point one way, no module imports itself back, and
each package's docstring maps exactly the modules it holds.

Every import counts: at module level, inside functions, and under
``TYPE_CHECKING``. ``omtp_drake/__init__.py`` is the lazy facade over the
layers (it imports nothing when loaded) and is left out of the import graph.
"""

from __future__ import annotations

import ast
import functools
import re
import subprocess
import sys
from collections.abc import Mapping
from collections.abc import Set as AbstractSet
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "omtp_drake"

#: Bottom to top: a unit imports only from a lower layer or from its own package.
LAYERS = {
    "errors": 0,
    "convex_pieces": 0,
    "lazy": 0,
    "assets": 1,
    "ur_arms": 2,
    "workspace": 2,  # (its xacro expansions are model-cache entries: assets)
    "scenario": 3,
    "cell": 4,
    "sim": 5,
    "control": 5,
    "viz": 6,
    "launch": 6,
    "tasks": 7,
    "script": 7,
    "batch": 8,
    "gazebo": 8,
    "ros": 9,
    "demos": 9,
    "bench_command": 9,
    "grading": 10,
    "ros2": 10,
    "cli": 11,
}


def _modules() -> dict[str, Path]:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        if parts == ("__init__",):
            continue
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found["omtp_drake." + ".".join(parts)] = path
    return found


def _imports(path: Path, modules: dict[str, Path]) -> set[str]:
    """The omtp_drake modules ``path`` imports (a name imported from a package
    counts as that package, or as its submodule when it is one)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("omtp_drake.")}
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("omtp_drake"):
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                out.add(sub if sub in modules else node.module)
    return out


def _unit(module: str) -> str:
    return module.split(".")[1]


@functools.cache
def _graph() -> dict[str, frozenset[str]]:
    """Each module's omtp_drake imports: read once per test process (the sources do not change
    while the tests run; four tests ask)."""
    modules = _modules()
    return {name: frozenset(_imports(path, modules) - {name}) for name, path in modules.items()}


def test_every_unit_has_a_layer():
    units = {_unit(m) for m in _modules()}
    assert units <= set(LAYERS), f"units without a layer: {sorted(units - set(LAYERS))}"


def test_layers_point_one_way():
    wrong = []
    for module, imported in _graph().items():
        for target in imported:
            if target == "omtp_drake":
                wrong.append(f"{module} imports the facade omtp_drake (import from the unit instead)")
                continue
            a, b = _unit(module), _unit(target)
            if a != b and LAYERS[b] >= LAYERS[a]:
                wrong.append(f"{module} (layer {LAYERS[a]}) imports {target} (layer {LAYERS[b]})")
    assert not wrong, "\n".join(sorted(wrong))


def _circles(graph: Mapping[str, AbstractSet[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components; each of 2+ modules is a circle."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return circles


def test_no_import_circle():
    assert not _circles(_graph()), f"import circles: {_circles(_graph())}"


def test_the_circle_check_finds_a_circle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _circles(graph) == [["a", "b", "c"]]


@pytest.mark.parametrize("heavy", ["ompl", "pydrake", "matplotlib", "dask"])
def test_importing_the_package_loads_nothing_heavy(heavy):
    code = (
        "import sys, omtp_drake\n"
        f"loaded = [m for m in sys.modules if m == {heavy!r} or m.startswith({heavy!r} + '.')]\n"
        "print(len(loaded))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "0"


def test_importing_the_command_line_loads_nothing_heavy():
    """A Dask worker of ``omtp-drake grade``/``batch`` imports ``omtp_drake.cli`` again as
    its ``__main__`` (multiprocessing's spawn): its commands' modules load only when a
    command line is parsed."""
    code = (
        "import sys, omtp_drake.cli\n"
        "heavy = ('ompl', 'pydrake', 'matplotlib', 'dask', 'numpy', 'omtp_drake.launch')\n"
        "print(sorted({m.split('.')[0] if not m.startswith('omtp_drake') else m for m in sys.modules\n"
        "              if any(m == h or m.startswith(h + '.') for h in heavy)}))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


#: A line of a package's map of its modules: ``- ``name``: its job``.
_MAP_LINE = re.compile(r"^ *- ``(\w+)``: \S", re.MULTILINE)


def _mapped(docstring: str) -> list[str]:
    """The module names a package docstring's map lists, in order."""
    return _MAP_LINE.findall(docstring)


def _packages() -> list[Path]:
    """Every package of omtp_drake, except the ROS-named shim packages under
    ``ros/shims`` (they mirror ROS's packages; ``ros`` maps ``shims`` itself)."""
    inits = PACKAGE.rglob("__init__.py")
    return sorted(p.parent for p in inits if "shims" not in p.relative_to(PACKAGE).parts)


def _members(package: Path) -> set[str]:
    """The modules of ``package``: its ``*.py`` files and its folders of Python code."""
    modules = {p.stem for p in package.glob("*.py") if p.name != "__init__.py"}
    folders = {d.name for d in package.iterdir() if d.is_dir() and any(d.rglob("*.py"))}
    return modules | folders


def test_the_map_reader_reads_map_lines_only():
    doc = "Modules:\n\n- ``driver``: runs it\n  - ``pool``: the parts\n``ledger`` is named in prose\n- ``x``:"
    assert _mapped(doc) == ["driver", "pool"]


@pytest.mark.parametrize("package", _packages(), ids=lambda p: p.relative_to(PACKAGE.parent).as_posix())
def test_each_package_docstring_maps_exactly_its_modules(package):
    doc = ast.get_docstring(ast.parse((package / "__init__.py").read_text())) or ""
    mapped = _mapped(doc)
    twice = sorted({m for m in mapped if mapped.count(m) > 1})
    members = _members(package)
    assert not twice, f"mapped twice: {twice}"
    assert set(mapped) == members, (
        f"not in the map: {sorted(members - set(mapped))}; mapped but absent: {sorted(set(mapped) - members)}"
    )


#: ``ros/``'s subpackages, one per ROS project it mirrors (see ``omtp_drake/ros/__init__.py``).
ROS_SUBPACKAGES = {"comm", "moveit", "tf", "gazebo", "flexbe", "run", "shims", "bag"}


def _outside_subpackages(ros: Path) -> list[str]:
    """The Python files and folders directly in ``ros`` that are not one of its subpackages."""
    stray = [p.name for p in ros.glob("*.py") if p.name != "__init__.py"]
    stray += [
        d.name for d in ros.iterdir() if d.is_dir() and d.name not in ROS_SUBPACKAGES and any(d.rglob("*.py"))
    ]
    return sorted(stray)


def test_ros_holds_only_its_subpackages():
    ros = PACKAGE / "ros"
    folders = {d.name for d in ros.iterdir() if d.is_dir() and any(d.rglob("*.py"))}
    assert folders == ROS_SUBPACKAGES, f"ros/'s subpackages changed: {sorted(folders ^ ROS_SUBPACKAGES)}"
    assert not _outside_subpackages(ros), f"modules outside ros/'s subpackages: {_outside_subpackages(ros)}"


def test_the_subpackage_check_finds_a_stray_module(tmp_path):
    (tmp_path / "__init__.py").write_text("")
    (tmp_path / "comm").mkdir()
    (tmp_path / "comm" / "client.py").write_text("")
    (tmp_path / "session.py").write_text("")
    (tmp_path / "grading").mkdir()
    (tmp_path / "grading" / "grade.py").write_text("")
    assert _outside_subpackages(tmp_path) == ["grading", "session.py"]


#: Imports that go around the door on purpose: the commands' parsers (``ros/*/cli.py``) take
#: the cell options every command shares (``--launch``, ``--world``) from ``launch.options``,
#: as ``omtp_drake/cli.py`` does; through ``_core`` they would load Drake to parse a command line.
_AROUND_THE_DOOR = {
    ("omtp_drake.ros.run.cli", "omtp_drake.launch.options"),
    ("omtp_drake.ros.flexbe.cli", "omtp_drake.launch.options"),
}


def _core_door_breaches(graph: Mapping[str, AbstractSet[str]]) -> list[str]:
    """Imports of a layer below ``ros`` by a ``ros`` module other than ``ros.comm._core``
    (``errors`` aside: every layer raises its errors; :data:`_AROUND_THE_DOOR` aside)."""
    door = "omtp_drake.ros.comm._core"
    return sorted(
        f"{module} imports {target}"
        for module, imported in graph.items()
        if _unit(module) == "ros" and module != door and ".shims." not in module
        for target in imported
        if target != "omtp_drake"
        and _unit(target) not in ("ros", "errors")
        and (module, target) not in _AROUND_THE_DOOR
    )


def test_ros_imports_the_core_through_its_one_door():
    """``ros/comm/_core.py`` says it is the one place the ROS layer imports the core from."""
    assert not _core_door_breaches(_graph())


def test_the_door_check_finds_a_module_going_around_it():
    graph = {
        "omtp_drake.ros.comm._core": {"omtp_drake.script"},
        "omtp_drake.ros.comm.session": {"omtp_drake.ros.comm._core", "omtp_drake.errors"},
        "omtp_drake.ros.moveit.config": {"omtp_drake.cell.arms"},
    }
    assert _core_door_breaches(graph) == ["omtp_drake.ros.moveit.config imports omtp_drake.cell.arms"]


def test_every_import_of_omtp_drake_names_a_module_that_exists():
    """An import of a moved or removed module fails here, not only when its function runs
    (imports inside functions count too)."""
    known = set(_modules()) | {"omtp_drake"}
    stale = {
        f"{name} imports {target}"
        for name, imported in _graph().items()
        for target in imported
        if target not in known
    }
    assert not stale, sorted(stale)


@pytest.mark.parametrize("init", ["__init__.py", "scenario/__init__.py", "batch/__init__.py"])
def test_a_lazy_packages_names_for_type_checkers_are_its_lazy_names(init):
    """A lazy package (omtp_drake.lazy) names each public name twice: in its map of where the
    name lives (read at run time) and in its ``if TYPE_CHECKING:`` imports (read by mypy). The
    two agree, name for name and module for module."""
    path = PACKAGE / init
    package = ".".join(["omtp_drake", *path.relative_to(PACKAGE).parent.parts])
    tree = ast.parse(path.read_text())
    (mapping,) = [
        node.value
        for node in tree.body
        if isinstance(node, ast.Assign)
        and isinstance(node.targets[0], ast.Name)
        and node.targets[0].id in ("_LAZY", "_MODULES")
    ]
    lazy = {
        name: module if not module.startswith(".") else package + module
        for name, module in ast.literal_eval(mapping).items()
    }
    (checking,) = [
        node
        for node in tree.body
        if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING"
    ]
    typed = {alias.name: node.module for node in checking.body for alias in node.names}  # type: ignore[attr-defined]
    assert typed == lazy
