"""A ROS 2 launch's nodes of the student's own workspace, found as ``ros2 run`` finds them.

``Node(package=P, executable=E)`` of a package in the workspace is, in its source folder
(nothing is built here):

========================================  ==============================================
the package                               the node
========================================  ==============================================
``ament_python``: ``E = module:function``  that function, with the package folder first on
in ``setup.py``'s (or ``setup.cfg``'s)    ``PYTHONPATH`` (what the installed console
``console_scripts``                       script runs)
a Python file named ``E`` (an             that file (``install(PROGRAMS ...)`` copies it
``ament_cmake`` package's script)         as it is)
========================================  ==============================================

Its command line is ``ros2 launch``'s: the node's ``arguments``, then ``--ros-args`` with
``-r __node:=NAME``, ``-r __ns:=NS``, each remapping as ``-r FROM:=TO`` and each
parameter as ``-p NAME:=VALUE`` (YAML; a nested dict's keys joined with dots).
Anything else (a compiled node) is not found: the caller warns.
"""

from __future__ import annotations

import ast
import configparser
import json
import shlex
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.roslaunch import Node


@dataclass(frozen=True)
class Ros2NodeProgram:
    """How to start a workspace's ROS 2 Python node ``name``: a file, or a console script's
    ``module:function`` with ``pythonpath`` first on the path."""

    name: str
    path: Path
    entry: str = ""
    pythonpath: Optional[Path] = None

    def command(self, python: str) -> list[str]:
        """The command line before the node's own arguments, run by ``python``."""
        if not self.entry:
            return [python, str(self.path)]
        module, function = self.entry.split(":")
        runner = f"from {module} import {function} as main; raise SystemExit(main())"
        return [python, "-c", runner]


def console_scripts(package: Path) -> dict[str, str]:
    """The package's ``console_scripts`` (name -> ``module:function``) from ``setup.py``
    (read, not run: the literal ``entry_points`` of its ``setup(...)`` call) and ``setup.cfg``."""
    out: dict[str, str] = {}
    for line in _setup_py_scripts(package / "setup.py") + _setup_cfg_scripts(package / "setup.cfg"):
        name, sep, target = line.partition("=")
        if sep and ":" in target:
            out[name.strip()] = target.strip().split()[0]
    return out


def _setup_py_scripts(path: Path) -> list[str]:
    if not path.is_file():
        return []
    try:
        tree = ast.parse(path.read_text(), str(path))
    except SyntaxError as e:
        raise WorkspaceError(f"{path}:{e.lineno}: not Python ({e.msg})") from None
    for call in (n for n in ast.walk(tree) if isinstance(n, ast.Call)):
        for keyword in call.keywords:
            if keyword.arg == "entry_points" and isinstance(keyword.value, ast.Dict):
                for key, value in zip(keyword.value.keys, keyword.value.values):
                    if isinstance(key, ast.Constant) and key.value == "console_scripts":
                        items = getattr(value, "elts", [])
                        return [
                            e.value for e in items if isinstance(e, ast.Constant) and isinstance(e.value, str)
                        ]
    return []


def _setup_cfg_scripts(path: Path) -> list[str]:
    if not path.is_file():
        return []
    config = configparser.ConfigParser()
    config.read(path)
    text = config.get("options.entry_points", "console_scripts", fallback="")
    return [line for line in text.splitlines() if line.strip()]


def find_program(package: Path, executable: str) -> Optional[Ros2NodeProgram]:
    """The node ``executable`` of the package in folder ``package`` (None: no Python node)."""
    entry = console_scripts(package).get(executable)
    if entry is not None:
        module = entry.split(":")[0]
        path = package.joinpath(*module.split(".")).with_suffix(".py")
        if not path.is_file():
            raise WorkspaceError(
                f"{package / 'setup.py'}: console script {executable} = {entry}: no file {path}"
            )
        return Ros2NodeProgram(executable, path, entry, package)
    for path in sorted(p for p in package.rglob(executable) if p.is_file()):
        if path.suffix == ".py" or path.read_bytes()[:64].split(b"\n")[0].endswith((b"python", b"python3")):
            return Ros2NodeProgram(executable, path)
    return None


def ros_arguments(node: Node, params: Mapping[str, Any]) -> tuple[str, ...]:
    """The node's command line as ``ros2 launch`` gives it (see the module doc)."""
    argv = [*shlex.split(node.args), "--ros-args", "-r", f"__node:={node.name.rsplit('/', 1)[-1]}"]
    if node.namespace.strip("/"):
        argv += ["-r", f"__ns:={node.namespace}"]
    for source, target in node.remaps.items():
        argv += ["-r", f"{source}:={target}"]
    for name, value in _flat(params):
        argv += ["-p", f"{name}:={json.dumps(value)}"]
    return tuple(argv)


def _flat(params: Mapping[str, Any], prefix: str = "") -> Iterator[tuple[str, Any]]:
    for name, value in params.items():
        if isinstance(value, Mapping):
            yield from _flat(value, f"{prefix}{name}.")
        else:
            yield f"{prefix}{name}", value
