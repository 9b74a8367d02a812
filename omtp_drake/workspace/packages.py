"""``Workspace``: ROS packages and Gazebo models by name, found as rospack and Gazebo find them.

Packages:

* each folder given (``--workspace DIR``: a catkin or colcon ``src`` folder, a whole
  workspace, or one package), then each entry of ``ROS_PACKAGE_PATH``, is crawled as
  rospack crawls: a folder holding a ``package.xml`` is a package (named by its
  ``<name>``) and is not searched further; folders holding ``CATKIN_IGNORE``,
  ``COLCON_IGNORE`` or ``AMENT_IGNORE``, and hidden folders, are skipped. The first
  package found under a name wins, as in ``ROS_PACKAGE_PATH`` order.
* the project's stand-ins (``bundled``) come last: a student's own package of the
  same name is used instead of ours.

Gazebo models (``model://NAME/...``): each folder holding a ``model.config`` directly
under an entry of ``GAZEBO_MODEL_PATH`` or under a package's exported model path
(``<export><gazebo_ros gazebo_model_path="${prefix}/models"/></export>`` in its
``package.xml``, as gazebo_ros adds them), named by its folder.

:meth:`Workspace.package_map` gives Drake's ``PackageMap`` of both, so the parser
resolves ``package://`` and ``model://`` URIs as ROS and Gazebo do.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from omtp_drake.errors import MissingPackageError, WorkspaceError

#: Marker files that make catkin, colcon and ament skip a folder.
IGNORE_MARKERS = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE")

#: The command-line flag that adds a workspace folder (named in errors).
WORKSPACE_FLAG = "--workspace"


@dataclass(frozen=True)
class Workspace:
    """Packages and Gazebo models by name.

    Build one with :meth:`from_dirs`; ``packages`` and ``models`` map names to folders.
    """

    packages: Mapping[str, Path] = field(default_factory=dict)
    models: Mapping[str, Path] = field(default_factory=dict)
    #: The folders searched, in order (for error messages).
    searched: tuple[Path, ...] = ()

    @classmethod
    def from_dirs(
        cls,
        dirs: Iterable[str | os.PathLike] = (),
        *,
        environ: Mapping[str, str] | None = None,
        bundled: Iterable[str | os.PathLike] = (),
    ) -> Workspace:
        """The workspace of ``dirs`` (in order), then ``ROS_PACKAGE_PATH`` and
        ``GAZEBO_MODEL_PATH`` of ``environ`` (default ``os.environ``), then ``bundled``."""
        env = os.environ if environ is None else environ
        roots = [_existing_dir(d) for d in dirs]
        ros_path = [Path(p) for p in env.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
        model_path = [Path(p) for p in env.get("GAZEBO_MODEL_PATH", "").split(os.pathsep) if p]
        searched = [*roots, *(p for p in ros_path if p.is_dir()), *(Path(b) for b in bundled)]
        packages: dict[str, Path] = {}
        for root in searched:
            for name, folder in _crawl_packages(root):
                packages.setdefault(name, folder)
        model_dirs = [*roots, *(p for p in model_path if p.is_dir())]
        model_dirs += [d for folder in packages.values() for d in _exported_model_paths(folder)]
        models: dict[str, Path] = {}
        for folder in model_dirs:
            for name, path in _models_in(folder):
                models.setdefault(name, path)
        return cls(packages=packages, models=models, searched=tuple(searched))

    def package(self, name: str, *, needed_by: str | os.PathLike) -> Path:
        """The folder of package ``name``, or MissingPackageError naming who needs it."""
        try:
            return self.packages[name]
        except KeyError:
            raise MissingPackageError("package", name, needed_by, self._searched_text()) from None

    def model(self, name: str, *, needed_by: str | os.PathLike) -> Path:
        """The folder of Gazebo model ``name``, or MissingPackageError naming who needs it."""
        try:
            return self.models[name]
        except KeyError:
            raise MissingPackageError("Gazebo model", name, needed_by, self._searched_text()) from None

    def resolve(self, uri: str, *, needed_by: str | os.PathLike) -> Path:
        """The file a ``package://``, ``model://`` or ``file://`` URI, or a path relative to
        ``needed_by``'s folder, names."""
        for scheme, lookup in (("package://", self.package), ("model://", self.model)):
            if uri.startswith(scheme):
                name, _, rest = uri[len(scheme) :].partition("/")
                return lookup(name, needed_by=needed_by) / rest
        if uri.startswith("file://"):
            return Path(uri[len("file://") :])
        path = Path(uri)
        return path if path.is_absolute() else Path(needed_by).parent / path

    def package_map(self):
        """Drake's ``PackageMap`` of the packages and the Gazebo models (``model://NAME`` is
        resolved as a package of that name; a package wins over a model of the same name)."""
        from pydrake.multibody.parsing import PackageMap

        package_map = PackageMap.MakeEmpty()
        for name, folder in {**self.models, **self.packages}.items():
            package_map.Add(name, str(folder))
        return package_map

    def _searched_text(self) -> str:
        return ", ".join(str(p) for p in self.searched) or "no folder"


def _existing_dir(d: str | os.PathLike) -> Path:
    path = Path(d).expanduser().resolve()
    if not path.is_dir():
        raise WorkspaceError(f"{WORKSPACE_FLAG} {str(d)!r} is not a folder")
    return path


def _crawl_packages(root: Path) -> Iterable[tuple[str, Path]]:
    """(name, folder) of every package under ``root``, as rospack crawls."""
    for folder, subdirs, files in os.walk(root, followlinks=True):
        if any(marker in files for marker in IGNORE_MARKERS):
            subdirs[:] = []
            continue
        if "package.xml" in files:
            subdirs[:] = []
            yield _package_name(Path(folder) / "package.xml"), Path(folder)
            continue
        subdirs[:] = sorted(d for d in subdirs if not d.startswith("."))


def _package_name(manifest: Path) -> str:
    try:
        name = ET.parse(manifest).getroot().findtext("name")
    except ET.ParseError as e:
        raise WorkspaceError(f"{manifest}: not a package manifest: {e}") from None
    if not name or not name.strip():
        raise WorkspaceError(f"{manifest}: has no <name>")
    return name.strip()


def _exported_model_paths(package: Path) -> list[Path]:
    """The folders a package adds to Gazebo's model path (``gazebo_model_path``)."""
    try:
        export = ET.parse(package / "package.xml").getroot().find("export")
    except ET.ParseError:
        return []
    if export is None:
        return []
    out = []
    for element in export.iter("gazebo_ros"):
        value = element.get("gazebo_model_path")
        if value:
            out.append(Path(value.replace("${prefix}", str(package))))
    return [p for p in out if p.is_dir()]


def _models_in(folder: Path) -> Iterable[tuple[str, Path]]:
    """(name, folder) of each Gazebo model directly under ``folder`` (or ``folder`` itself)."""
    if (folder / "model.config").is_file():
        yield folder.name, folder
        return
    for child in sorted(folder.iterdir()):
        if child.is_dir() and (child / "model.config").is_file():
            yield child.name, child
