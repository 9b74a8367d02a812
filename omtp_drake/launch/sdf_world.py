"""A Gazebo world file (SDF) and the models it includes, as Gazebo places them.

:func:`read_world` reads a ``.world``: each ``<include>`` (``uri`` ``model://NAME``
found in the workspace's Gazebo models, its ``pose`` and ``name`` replacing the model's
own, ``static``) and each inline ``<model>``, with the plugins of the model and of its
links' sensors. Each model's SDF goes through Drake's parser too, so a model Drake
refuses is one error naming its file. Gazebo's own ``model://sun`` and
``model://ground_plane`` ship with Gazebo, not with the course: the sun lights the
scene and the ground plane is the cell's floor, so both are read as known and left out.
``<light>``, ``<physics>``, ``<scene>``, ``<gui>`` do not change the cell.
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.plugins import GazeboPlugin, plugins_in
from omtp_drake.launch.xml_lines import XmlFile, parse_xml
from omtp_drake.workspace import Workspace

#: Gazebo's own models that the cell already has (light, floor).
GAZEBO_BUILTIN_MODELS = ("sun", "ground_plane")
#: World elements that do not change the cell.
IGNORED_WORLD_TAGS = (
    "light",
    "physics",
    "scene",
    "gui",
    "gravity",
    "magnetic_field",
    "atmosphere",
    "spherical_coordinates",
    "state",
    "wind",
)


@dataclass
class WorldModel:
    """A model of the world: its name, pose in world, SDF element, file and plugins."""

    name: str
    X_WM: RigidTransform
    element: ET.Element
    where: str
    plugins: list[GazeboPlugin] = field(default_factory=list)
    #: The pose as written (x y z roll pitch yaw), so a camera keeps the student's numbers.
    pose: tuple[float, ...] = (0.0,) * 6

    def sensors(self, kind: str) -> list[ET.Element]:
        return [s for s in self.element.iter("sensor") if s.get("type") == kind]


@dataclass
class World:
    file: Path
    models: list[WorldModel] = field(default_factory=list)


def sdf_pose(text: str | None, where: str) -> RigidTransform:
    """An SDF ``<pose>`` (``x y z roll pitch yaw``)."""
    values = pose_values(text, where)
    return RigidTransform(RollPitchYaw(values[3:]), values[:3])


def pose_values(text: str | None, where: str) -> tuple[float, ...]:
    """The 6 numbers of an SDF ``<pose>`` (zeros when there is none)."""
    if not text:
        return (0.0,) * 6
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) != 6:
        raise WorkspaceError(f"{where}: <pose> needs 6 numbers (x y z roll pitch yaw), got {text.strip()!r}")
    return tuple(values)


def read_world(path: Path, workspace: Workspace) -> World:
    """The world file ``path``'s models (see module doc)."""
    doc = parse_xml(path)
    world = doc.root.find("world") if doc.root.tag == "sdf" else None
    if world is None:
        raise WorkspaceError(f"{path}: not a Gazebo world (an <sdf> with a <world>)")
    out = World(path)
    included: list[tuple[Path, Path]] = []
    for element in world:
        where = doc.where(element)
        if element.tag == "include":
            model = _included(doc, element, workspace, included)
            if model is not None:
                out.models.append(model)
        elif element.tag == "model":
            pose = pose_values(element.findtext("pose"), where)
            out.models.append(world_model(element.get("name", ""), pose, element, where))
        elif element.tag not in IGNORED_WORLD_TAGS and element.tag != "plugin":
            raise WorkspaceError(f"{where}: <{element.tag}> in a world is not supported")
    check_with_drake([d for d, _ in included], [f for _, f in included], workspace)
    return out


def _included(
    doc: XmlFile, element: ET.Element, workspace: Workspace, included: list[tuple[Path, Path]]
) -> WorldModel | None:
    where = doc.where(element)
    uri = (element.findtext("uri") or "").strip()
    if not uri.startswith("model://"):
        raise WorkspaceError(f"{where}: <include> uri {uri!r} is not supported; valid: model://NAME")
    name = uri[len("model://") :].strip("/")
    if name in GAZEBO_BUILTIN_MODELS:
        return None
    folder = workspace.model(name, needed_by=where)
    sdf_file = folder / _sdf_name(folder / "model.config")
    model_doc = parse_xml(sdf_file)
    model = model_doc.root.find("model")
    if model is None:
        raise WorkspaceError(f"{sdf_file}: has no <model>")
    included.append((folder, sdf_file))
    pose = pose_values(element.findtext("pose") or model.findtext("pose"), where)
    placed = (element.findtext("name") or "").strip() or model.get("name", name)
    return world_model(placed, pose, model, str(sdf_file))


def world_model(name: str, pose: tuple[float, ...], element: ET.Element, where: str) -> WorldModel:
    """The model ``element`` named ``name`` at ``pose`` (x y z roll pitch yaw) in world."""
    plugins = plugins_in(element, where)
    for link in element.iter("link"):
        plugins += plugins_in(link, where, link=link.get("name", ""))
    X_WM = RigidTransform(RollPitchYaw(pose[3:]), pose[:3])
    return WorldModel(name, X_WM, element, where, plugins, tuple(pose))


def _sdf_name(config: Path) -> str:
    """The SDF file a ``model.config`` names (``<sdf>model.sdf</sdf>``)."""
    if not config.is_file():
        return "model.sdf"
    root = parse_xml(config).root
    names = [e.text.strip() for e in root.findall("sdf") if e.text and e.text.strip()]
    return names[-1] if names else "model.sdf"


def check_with_drake(model_dirs: list[Path], sdf_files: list[Path], workspace: Workspace) -> None:
    """Drake's parser reads the models (folders with their SDF files): all in one parse (one
    libsdformat session costs about as much as each model alone); if it refuses, each
    alone, so the error names the file it refuses."""
    if not model_dirs:
        return
    includes = "".join(
        f"<include><uri>{folder}</uri><name>model_{i}</name></include>" for i, folder in enumerate(model_dirs)
    )
    world = f'<?xml version="1.0"?><sdf version="1.6"><world name="check">{includes}</world></sdf>'
    if _drake_refusal(lambda parser: parser.AddModelsFromString(world, "sdf"), workspace) is None:
        return
    for sdf_file in sdf_files:
        refusal = _drake_refusal(lambda parser, f=sdf_file: parser.AddModels(str(f)), workspace)
        if refusal is not None:
            raise WorkspaceError(f"{sdf_file}: Drake's SDF parser refuses it: {refusal}")
    raise WorkspaceError(f"{', '.join(map(str, sdf_files))}: Drake's SDF parser refuses them together")


def _drake_refusal(parse, workspace: Workspace) -> str | None:
    """The first line of Drake's refusal of ``parse(parser)`` (None: it parsed)."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    plant = MultibodyPlant(0.0)  # kept alive while the parser uses it
    parser = Parser(plant)
    parser.package_map().AddMap(workspace.package_map())
    # Drake warns that it ignores <plugin>, <sensor> and <gravity>: those are read here.
    drake_log = logging.getLogger("drake")
    level = drake_log.level
    drake_log.setLevel(max(level, logging.ERROR))
    try:
        parse(parser)
    except RuntimeError as e:
        return str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    finally:
        drake_log.setLevel(level)
    return None
