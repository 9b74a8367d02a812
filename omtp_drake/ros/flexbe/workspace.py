"""Catkin workspaces: their packages, importable Python and FlexBE behaviour manifests.

A workspace is a catkin ``src`` folder. Every folder under it with a
``package.xml`` is a package, named by the file's ``<name>`` (``rospkg`` finds
it); a package's ``src`` folder holds its Python packages (catkin's
``setup.py`` layout), which a run puts on ``sys.path``. Folders with a
``CATKIN_IGNORE`` file, and hidden ones, are skipped, as catkin does.

A behaviour is found by its manifest (``<pkg>/manifest/*.xml``: ``<behavior
name="...">`` with ``<executable package_path="pkg.module" class="Class"/>``),
by the name ``be_launcher -b`` takes (surrounding blanks ignored, as FlexBE's
generated names often end in one), or by the path of its ``*_sm.py``.
"""

from __future__ import annotations

import ast
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError, UnknownNameError


@dataclass(frozen=True)
class BehaviorEntry:
    """A behaviour: its name, its module and class, and where they are."""

    name: str
    module: str
    class_name: str
    source: Path
    manifest: Optional[Path] = None


def _package_name(package_xml: Path) -> str:
    try:
        root = ET.parse(package_xml).getroot()
    except ET.ParseError as e:
        raise ConfigError(f"{package_xml} is no valid package.xml: {e}") from None
    name = (root.findtext("name") or "").strip()
    if not name:
        raise ConfigError(f"{package_xml} has no <name>")
    return name


def find_packages(roots: Sequence[Path]) -> dict[str, Path]:
    """``name -> folder`` of every package under ``roots`` (the first of a name wins, as
    on ROS_PACKAGE_PATH)."""
    packages: dict[str, Path] = {}
    for root in roots:
        stack = [Path(root)]
        while stack:
            folder = stack.pop()
            if (folder / "CATKIN_IGNORE").exists():
                continue
            if (folder / "package.xml").is_file():
                packages.setdefault(_package_name(folder / "package.xml"), folder)
                continue  # catkin does not look for packages inside a package
            stack.extend(
                sorted(
                    (p for p in folder.iterdir() if p.is_dir() and not p.name.startswith(".")), reverse=True
                )
            )
    return packages


class Workspaces:
    """The packages of one or more catkin ``src`` folders."""

    def __init__(self, folders: Sequence[str | Path]):
        if not folders:
            raise ConfigError("flexbe-run needs at least one --workspace DIR (a catkin src folder)")
        self.roots = []
        for folder in folders:
            path = Path(folder).resolve()
            if not path.is_dir():
                raise ConfigError(f"workspace {str(folder)!r} is no folder")
            self.roots.append(path)
        self.packages = find_packages(self.roots)

    def python_paths(self) -> list[Path]:
        """The ``src`` folders of the packages (what catkin's devel space makes importable)."""
        return [p / "src" for p in self.packages.values() if (p / "src").is_dir()]

    def behaviors(self) -> list[BehaviorEntry]:
        entries = []
        for package in self.packages.values():
            for manifest in sorted((package / "manifest").glob("*.xml")):
                entry = self._from_manifest(manifest)
                if entry is not None:
                    entries.append(entry)
        return entries

    def _from_manifest(self, manifest: Path) -> Optional[BehaviorEntry]:
        try:
            root = ET.parse(manifest).getroot()
        except ET.ParseError as e:
            raise ConfigError(f"behaviour manifest {manifest} is no valid XML: {e}") from None
        executable = root.find("executable")
        if root.tag != "behavior" or executable is None:
            return None
        module = executable.get("package_path", "")
        source = self._module_file(module)
        return BehaviorEntry(
            name=root.get("name", ""),
            module=module,
            class_name=executable.get("class", ""),
            source=source if source is not None else manifest,
            manifest=manifest,
        )

    def _module_file(self, module: str) -> Optional[Path]:
        parts = module.split(".")
        for folder in self.python_paths():
            candidate = folder.joinpath(*parts).with_suffix(".py")
            if candidate.is_file():
                return candidate
        return None

    def find(self, behavior: str) -> BehaviorEntry:
        """The behaviour named ``behavior`` (a manifest's name) or at that ``*_sm.py`` path."""
        if behavior.endswith(".py"):
            return self._from_path(Path(behavior))
        matches = [e for e in self.behaviors() if e.name.strip() == behavior.strip()]
        if len(matches) > 1:
            where = "; ".join(str(e.manifest) for e in matches)
            raise ConfigError(f"two behaviours are named {behavior!r}: {where}; pass the path of its *_sm.py")
        if not matches:
            names = [e.name.strip() for e in self.behaviors()]
            raise UnknownNameError("behaviour", behavior, names)
        return matches[0]

    def _from_path(self, path: Path) -> BehaviorEntry:
        path = path.resolve()
        if not path.is_file():
            raise ConfigError(f"behaviour file {str(path)!r} does not exist")
        for entry in self.behaviors():
            if entry.source == path:
                return entry
        for folder in self.python_paths():
            if folder in path.parents:
                module = ".".join(path.relative_to(folder).with_suffix("").parts)
                return BehaviorEntry(path.stem, module, _behavior_class(path), path)
        roots = ", ".join(str(r) for r in self.roots)
        raise ConfigError(f"{path} is not in a package's src folder of the workspaces ({roots})")


def _behavior_class(path: Path) -> str:
    """The class of a ``*_sm.py`` that derives from ``Behavior``."""
    tree = ast.parse(path.read_text(), str(path))
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and any(
            getattr(base, "id", getattr(base, "attr", "")) == "Behavior" for base in node.bases
        ):
            return node.name
    raise ConfigError(f"{path} defines no class derived from flexbe_core's Behavior")


class ResourceNotFound(Exception):
    """rospkg's error for a package it cannot find."""


def _known_packages() -> dict[str, Path]:
    """The run's workspace packages; outside a FlexBE run, those on ROS_PACKAGE_PATH."""
    import os

    from omtp_drake.errors import SimulationError
    from omtp_drake.ros.flexbe.context import current_run

    try:
        return dict(current_run().packages)
    except SimulationError:
        roots = [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
        return find_packages([r for r in roots if r.is_dir()])


class RosPack:
    """rospkg.RosPack over the workspaces' packages."""

    def __init__(self, ros_paths: Optional[Sequence[str]] = None):
        self._packages = find_packages([Path(p) for p in ros_paths]) if ros_paths else _known_packages()

    def get_path(self, name: str) -> str:
        if name not in self._packages:
            known = ", ".join(sorted(self._packages)) or "none"
            raise ResourceNotFound(f"{name} (the workspaces' packages: {known})")
        return str(self._packages[name])

    def list(self) -> list[str]:
        return sorted(self._packages)
