"""A model from a description file (a student's URDF, xacro or SDF) in the scenario.

:class:`ModelConfig` is the scenario's entry for any model the cell does not build
itself: the expanded description (URDF or SDF text), where it came from, its name and
pose (as ``spawn_model``'s ``-model``, ``-x -y -z -R -P -Y``), whether it is static,
the packages its ``package://`` and ``model://`` URIs name, and its Gazebo tags, read
once into typed settings (:mod:`omtp_drake.scenario.gazebo_tags`).
:func:`model_from_file` makes one from a file in a workspace (xacro expanded there).
The cell loads it with Drake's Parser (:mod:`omtp_drake.cell.described_models`).
"""

import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario.gazebo_parse import check_masses, description_format, parse_gazebo_tags, root_name
from omtp_drake.scenario.gazebo_tags import GazeboExtensions
from omtp_drake.workspace import Workspace, expand_xacro_in

#: The description formats Drake's parser reads.
FORMATS = ("urdf", "sdf")


@dataclass
class ModelConfig:
    """A model from a description file, placed in the world as ``spawn_model`` places it."""

    #: The model's name (Gazebo's model name; a tf frame is each of its links).
    name: str = ""
    #: The file it came from (named in errors; relative URIs are resolved next to it).
    file: str = ""
    #: The description: URDF or SDF text, xacro already expanded.
    description: str = ""
    format: str = "urdf"
    #: Pose of the model in the world (``-x -y -z``, ``-R -P -Y``).
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: Welded where it stands (Gazebo's ``<static>``); a URDF with a ``world`` link is
    #: fixed by its own joint.
    static: bool = False
    #: A frame of the cell the model is welded to (a link of a course piece: it moves with
    #: it); ``xyz``/``rpy`` are then its pose in that frame. '' for the world.
    parent: str = ""
    #: package or Gazebo model name -> folder, for ``package://`` and ``model://``.
    packages: dict[str, str] = field(default_factory=dict)
    gazebo: GazeboExtensions = field(default_factory=GazeboExtensions)
    #: Links whose collision meshes are loaded as convex pieces that keep them open (a
    #: bin of mesh collisions; one convex hull would close it), see ``assets.drake_ready_meshes``.
    open_links: list[str] = field(default_factory=list)

    def validate(self) -> None:
        """Raises ConfigError naming the file and the bad value."""
        where = self.file or f"models[{self.name}]"
        if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", self.name or ""):
            raise ConfigError(f"{where}: model name {self.name!r} must be letters, digits and '_'")
        if self.format not in FORMATS:
            raise UnknownNameError(f"format of {where}", self.format, FORMATS)
        for key in ("xyz", "rpy"):
            if len(getattr(self, key)) != 3:
                raise ConfigError(f"{where}: {key} needs 3 numbers, got {getattr(self, key)!r}")
        if not self.description.strip():
            raise ConfigError(f"{where}: the description is empty")
        found = description_format(self.description, where)
        if found != self.format:
            raise ConfigError(f"{where}: format {self.format!r}, but the description is {found.upper()}")
        check_masses(self.description, where)
        self.gazebo.validate(where)
        links = {e.get("name", "") for e in ET.fromstring(self.description).iter("link")}
        for link in self.open_links:
            if link not in links:
                raise UnknownNameError(f"link of {where}'s open_links", link, links)
        for sensor in self.gazebo.sensors:  # a typed entry's sensor sits on a link of its model
            if sensor.link not in links:
                raise UnknownNameError(f"link of {where}'s sensor {sensor.name!r}", sensor.link, links)


def model_from_file(
    path: str | os.PathLike,
    workspace: Optional[Workspace] = None,
    *,
    name: str = "",
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0),
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0),
    static: bool = False,
    args: Optional[dict[str, str]] = None,
) -> ModelConfig:
    """The model of the URDF, xacro or SDF file ``path`` (xacro expanded with ``args``,
    ``$(find)`` in ``workspace``), named ``name`` (default: the file's robot or model
    name), at ``xyz``/``rpy``; checked (ConfigError naming the file and the value)."""
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"{path}: no such file")
    workspace = workspace or file_workspace(path)
    if path.suffix == ".sdf" or path.name.endswith(".world"):
        text = path.read_text()
    else:
        text = expand_xacro_in(workspace, path, args)
    return model_from_text(text, str(path), workspace, name=name, xyz=xyz, rpy=rpy, static=static)


def model_from_text(
    text: str,
    file: str,
    workspace: Workspace,
    *,
    name: str = "",
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0),
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0),
    static: bool = False,
) -> ModelConfig:
    """The model of an already expanded description (e.g. a launch file's
    ``robot_description``); ``file`` names where it came from."""
    model = ModelConfig(
        name=name or root_name_of(text, file),
        file=file,
        description=text,
        format=description_format(text, file),
        xyz=[float(v) for v in xyz],
        rpy=[float(v) for v in rpy],
        static=static,
        packages={k: str(v) for k, v in {**workspace.models, **workspace.packages}.items()},
        gazebo=parse_gazebo_tags(text, file),
    )
    model.validate()
    return model


def root_name_of(text: str, file: str) -> str:
    name = root_name(text)
    if not name:
        raise ConfigError(f"{file}: the robot or model has no name; give one (spawn_model's -model)")
    return name


def file_workspace(path: str | os.PathLike, dirs: Sequence[str | os.PathLike] = ()) -> Workspace:
    """The workspace of the file ``path``: ``dirs`` (``--workspace``), ``ROS_PACKAGE_PATH``,
    then the package holding ``path`` (if any; nothing above it is crawled: other packages
    come from ``dirs`` or ``ROS_PACKAGE_PATH``)."""
    resolved = Path(path).resolve()
    roots = [f for f in resolved.parents if (f / "package.xml").is_file()][:1]
    return Workspace.from_dirs(dirs, bundled=roots)
