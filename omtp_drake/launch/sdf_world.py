"""A Gazebo world file (SDF) and the models it includes, as Gazebo places them.

:func:`read_world` reads a ``.world`` as Gazebo 9's sdformat does: each ``<include>``
(``uri`` ``model://NAME`` found in the workspace's Gazebo models and ``GAZEBO_MODEL_PATH``,
or a model folder's path; its ``name``, ``pose`` and ``static`` replacing the model's
own) and each inline ``<model>``, with the plugins of the model and of its links'
sensors, its pose in the world (``relative_to`` a model or ``<frame>`` of the world
before it, SDF 1.7+) and whether it is static. Each model's SDF goes through Drake's
parser too, so a model Drake refuses is one error naming its file.

Gazebo's own ``model://sun`` and ``model://ground_plane`` ship with Gazebo, not with the
course: the project's stand-ins are the cell's light and floor. ``<gravity>`` is the
world's gravity; ``<physics>``'s ``max_step_size`` is noted (the cell keeps its own
step). What sdformat reads but warns about (an element SDF does not define, a URDF
``<joint>`` or a stray ``<xacro:...>`` call under ``<world>``) is one warning line naming
``file:line``, and the rest of the world loads; what sdformat refuses (XML that is not
well formed, a ``<pose>`` that is not 6 numbers) is one error. The cases are listed in
``docs/own_files.md``.
"""

from __future__ import annotations

import copy
import dataclasses
import logging
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.cell.described_models import drake_errors
from omtp_drake.errors import ConfigError, MissingPackageError, WorkspaceError
from omtp_drake.launch.parse_verdicts import known_accepted, remember_accepted
from omtp_drake.launch.plugins import GazeboPlugin, plugins_in
from omtp_drake.launch.sdf_warnings import not_sdf_line, strip_strays
from omtp_drake.launch.xml_lines import XmlFile, parse_xml
from omtp_drake.scenario import ModelConfig
from omtp_drake.scenario.models import model_from_text
from omtp_drake.workspace import Workspace

#: Gazebo's own models that the cell already has (light, floor): the project's stand-ins.
GAZEBO_BUILTIN_MODELS = ("sun", "ground_plane")
#: World elements SDF defines that do not change the cell (read, not used).
IGNORED_WORLD_TAGS = (
    "light",
    "scene",
    "gui",
    "magnetic_field",
    "atmosphere",
    "spherical_coordinates",
    "state",
    "wind",
    "audio",
    "plugin",
)
#: World elements SDF defines that the cell has no counterpart for (one warning each).
UNSUPPORTED_WORLD_TAGS = ("actor", "road", "population")
#: Models of Gazebo's online model database (models.gazebosim.org) the tutorials include.
ONLINE_DATABASE = "http://models.gazebosim.org"


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
    #: Gazebo's ``<static>`` (the include's, else the model's own).
    static: bool = False
    #: The folder its relative URIs are resolved in (the model's file's folder).
    folder: Path | None = None
    #: The SDF version of the file the model element was read from.
    version: str = "1.6"
    #: That file, for its elements' lines (None: not known).
    doc: XmlFile | None = None

    def where_of(self, element: ET.Element) -> str:
        """``file:line`` of an element of the model (the model's place when not known)."""
        return self.doc.where(element) if self.doc is not None and self.doc.line(element) else self.where

    def sensors(self, kind: str) -> list[ET.Element]:
        return [s for s in self.element.iter("sensor") if s.get("type") == kind]


@dataclass
class World:
    file: Path
    models: list[WorldModel] = field(default_factory=list)
    #: What sdformat would warn about, one line each (``file:line: ...``).
    warnings: list[str] = field(default_factory=list)
    #: ``<gravity>`` (m/s^2 in world), None when the world does not set it.
    gravity: tuple[float, float, float] | None = None
    #: ``<physics>``'s ``max_step_size`` (s), None when not given.
    max_step_size: float | None = None


def sdf_pose(text: str | None, where: str) -> RigidTransform:
    """An SDF ``<pose>`` (``x y z roll pitch yaw``)."""
    values = pose_values(text, where)
    return RigidTransform(RollPitchYaw(values[3:]), values[:3])


def pose_values(text: str | None, where: str) -> tuple[float, ...]:
    """The 6 numbers of an SDF ``<pose>`` (zeros when there is none); each finite."""
    if not text or not text.strip():
        return (0.0,) * 6
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) != 6:
        raise WorkspaceError(f"{where}: <pose> needs 6 numbers (x y z roll pitch yaw), got {text.strip()!r}")
    if not all(math.isfinite(v) for v in values):
        raise WorkspaceError(f"{where}: <pose> {text.strip()!r} has a value that is not a finite number")
    return tuple(values)


def _is_true(text: str | None) -> bool:
    return (text or "").strip().lower() in ("true", "1")


class _WorldReader:
    """Reads one world file's elements into a :class:`World` (see module doc)."""

    def __init__(self, doc: XmlFile, workspace: Workspace):
        self.doc = doc
        self.workspace = workspace
        self.out = World(doc.path)
        self.version = sdf_version(doc)
        #: Poses in world of the models and frames read so far (``relative_to`` targets).
        self.frames: dict[str, RigidTransform] = {"world": RigidTransform()}
        #: The included models: folder, file, its document, its model element, SDF version.
        self.included: list[tuple[Path, Path, XmlFile, ET.Element, str]] = []

    def element(self, element: ET.Element) -> None:
        where = self.doc.where(element)
        tag = element.tag
        if tag == "include":
            self._include(element, where)
        elif tag == "model":
            self.out.warnings += strip_strays(self.doc, element)
            pose, X_WM = self._pose(element, where)
            folder = self.doc.path.parent
            self.out.warnings += check_model(self.doc, element, self.version, folder, self.workspace)
            name = element.get("name", "")
            self._add(world_model(name, pose, element, where, X_WM=X_WM, version=self.version, doc=self.doc))
        elif tag == "frame":
            self.frames[element.get("name", "")] = self._pose(element, where)[1]
        elif tag == "gravity":
            self.out.gravity = _vector3(element.text, where, "gravity")
        elif tag == "physics":
            step = element.findtext("max_step_size")
            if step is not None and step.strip():
                self.out.max_step_size = _positive(step, where, "max_step_size")
        elif tag in UNSUPPORTED_WORLD_TAGS:
            self.out.warnings.append(f"{where}: <{tag}> is not in the cell; ignored")
        elif tag not in IGNORED_WORLD_TAGS:
            self.out.warnings.append(not_sdf_line(element, where))

    def _pose(self, element: ET.Element, where: str) -> tuple[tuple[float, ...], RigidTransform]:
        """The element's pose as written, and in world (``relative_to`` resolved)."""
        pose_element = element.find("pose")
        text = pose_element.text if pose_element is not None else None
        pose = pose_values(text, where)
        X = RigidTransform(RollPitchYaw(pose[3:]), pose[:3])
        relative_to = (pose_element.get("relative_to") or "").strip() if pose_element is not None else ""
        if relative_to:
            if relative_to not in self.frames:
                raise WorkspaceError(
                    f"{where}: <pose relative_to={relative_to!r}>: no such model or frame before it; "
                    f"valid: {', '.join(self.frames)}"
                )
            X = self.frames[relative_to] @ X
        return pose, X

    def _add(self, model: WorldModel) -> None:
        self.frames[model.name] = model.X_WM
        self.out.models.append(model)

    def _include(self, element: ET.Element, where: str) -> None:
        uri = (element.findtext("uri") or "").strip()
        folder = self._include_folder(uri, where)
        if folder is None:
            return
        sdf_file = folder / _sdf_name(folder / "model.config")
        model_doc = parse_xml(sdf_file)
        model = model_doc.root.find("model")
        if model is None:
            raise WorkspaceError(f"{sdf_file}: has no <model>")
        self.out.warnings += strip_strays(model_doc, model)
        self.included.append((folder, sdf_file, model_doc, model, sdf_version(model_doc)))
        if element.find("pose") is not None:
            pose, X_WM = self._pose(element, where)
        else:
            pose = pose_values(model.findtext("pose"), model_doc.where(model))
            X_WM = RigidTransform(RollPitchYaw(pose[3:]), pose[:3])
        placed = (element.findtext("name") or "").strip() or model.get("name", folder.name)
        static = element.findtext("static")
        version = sdf_version(model_doc)
        found = world_model(
            placed, pose, model, str(sdf_file), X_WM=X_WM, version=version, folder=folder, doc=model_doc
        )
        if static is not None:
            found.static = _is_true(static)
        self._add(found)

    def _include_folder(self, uri: str, where: str) -> Path | None:
        """The model folder an include's uri names (None: Gazebo's own sun/ground plane)."""
        if uri.startswith(("http://", "https://")):
            raise WorkspaceError(
                f"{where}: <include> uri {uri!r} is on the web (Gazebo Fuel or its online model "
                "database); omtp-drake downloads nothing: put the model's folder in GAZEBO_MODEL_PATH "
                "or a --workspace folder and include it as model://NAME"
            )
        if uri.startswith("model://"):
            name = uri[len("model://") :].strip("/").split("/")[0]
            if name in GAZEBO_BUILTIN_MODELS:
                return None
            try:
                return self.workspace.model(name, needed_by=where)
            except MissingPackageError as e:
                # One line that also says where Gazebo would have found it.
                e.args = (
                    f"{e.args[0]}; Gazebo 9 downloads a model no folder has from its online model "
                    f"database ({ONLINE_DATABASE}); omtp-drake downloads nothing",
                )
                raise
        path = Path(uri[len("file://") :] if uri.startswith("file://") else uri)
        if not path.is_absolute():
            path = self.doc.path.parent / path
        if not path.is_dir():
            raise WorkspaceError(
                f"{where}: <include> uri {uri!r} is no model folder; valid: model://NAME, or a folder path"
            )
        return path


def sdf_version(doc: XmlFile) -> str:
    """The ``<sdf version>`` of a file (``MAJOR.MINOR``), as sdformat requires it."""
    version = doc.root.get("version", "1.6").strip()
    if not re.fullmatch(r"\d+\.\d+", version):
        raise WorkspaceError(
            f"{doc.where(doc.root)}: <sdf version={version!r}> is not an SDF version (e.g. 1.6)"
        )
    return version


def _vector3(text: str | None, where: str, what: str) -> tuple[float, float, float]:
    try:
        values = [float(v) for v in (text or "").split()]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise WorkspaceError(f"{where}: <{what}> needs 3 finite numbers, got {(text or '').strip()!r}")
    return values[0], values[1], values[2]


def _positive(text: str, where: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise WorkspaceError(f"{where}: <{what}> {text.strip()!r} must be a number > 0")
    return value


def read_world(path: Path, workspace: Workspace) -> World:
    """The world file ``path``'s models (see module doc)."""
    doc = parse_xml(path)
    world = doc.root.find("world") if doc.root.tag == "sdf" else None
    if world is None:
        raise WorkspaceError(f"{path}: not a Gazebo world (an <sdf> with a <world>)")
    reader = _WorldReader(doc, workspace)
    for element in world:
        reader.element(element)
    included = reader.included
    if not with_drake([folder for folder, *_ in included], workspace):
        for folder, sdf_file, model_doc, model, version in included:  # which, and why (or only warnings)
            reader.out.warnings += check_model(model_doc, model, version, folder, workspace, sdf_file)
    return reader.out


def world_model(
    name: str,
    pose: tuple[float, ...],
    element: ET.Element,
    where: str,
    *,
    X_WM: RigidTransform | None = None,
    version: str = "1.6",
    folder: Path | None = None,
    doc: XmlFile | None = None,
) -> WorldModel:
    """The model ``element`` named ``name`` at ``pose`` (x y z roll pitch yaw) in world
    (``X_WM``: the pose in world when it is relative to another frame); ``doc``, the file
    it is read from, gives each plugin its own ``file:line``."""
    plugins = plugins_in(element, where)
    for link in element.iter("link"):
        plugins += plugins_in(link, where, link=link.get("name", ""))
    if doc is not None:
        plugins = [dataclasses.replace(p, where=doc.where(p.element)) for p in plugins]
    if X_WM is None:
        X_WM = RigidTransform(RollPitchYaw(pose[3:]), pose[:3])
    static = _is_true(element.findtext("static"))
    return WorldModel(name, X_WM, element, where, plugins, tuple(pose), static, folder, version, doc)


def _sdf_name(config: Path) -> str:
    """The SDF file a ``model.config`` names (``<sdf>model.sdf</sdf>``)."""
    if not config.is_file():
        return "model.sdf"
    root = parse_xml(config).root
    names = [e.text.strip() for e in root.findall("sdf") if e.text and e.text.strip()]
    return names[-1] if names else "model.sdf"


def with_drake(model_dirs: list[Path], workspace: Workspace) -> bool:
    """Whether Drake's parser reads the model folders all in one parse (one libsdformat
    session costs about as much as each model alone); when not, the caller checks each."""
    if not model_dirs:
        return True
    includes = "".join(
        f"<include><uri>{folder}</uri><name>model_{i}</name></include>" for i, folder in enumerate(model_dirs)
    )
    world = f'<?xml version="1.0"?><sdf version="1.6"><world name="check">{includes}</world></sdf>'
    if known_accepted(model_dirs, workspace):
        return True
    if _drake_refusal(lambda parser: parser.AddModelsFromString(world, "sdf"), workspace) is not None:
        return False
    remember_accepted(model_dirs, workspace)
    return True


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
        with drake_errors() as errors:
            parse(parser)
    except (RuntimeError, ValueError) as e:  # (libsdformat's stoi of a bad version: ValueError)
        return str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    finally:
        drake_log.setLevel(level)
    return errors[0] if errors else None


def model_text(element: ET.Element, version: str, folder: Path) -> str:
    """The SDF document of the model ``element`` alone, its relative URIs resolved in ``folder``."""
    element = copy.deepcopy(element)
    for uri in element.iter("uri"):
        text = (uri.text or "").strip()
        if text and "://" not in text and not Path(text).is_absolute():
            uri.text = str(folder / text)
    return f'<sdf version="{version}">{ET.tostring(element, encoding="unicode")}</sdf>'


#: libsdformat's words for an element SDF does not define (Drake's parser refuses it).
_NOT_SDF = re.compile(
    r"At XML path (\S+): XML Element\[[^\]]+\], child of element\[[^\]]+\], not defined in SDF"
)


def check_model(
    doc: XmlFile,
    element: ET.Element,
    version: str,
    folder: Path,
    workspace: Workspace,
    sdf_file: Path | None = None,
) -> list[str]:
    """Drake's parser reads the model ``element`` of ``doc`` (an included model: its file
    ``sdf_file`` first, so a refusal names the file's own line): an element SDF does not
    define, which sdformat only warns about (and Drake refuses), is removed with one
    warning naming ``file:line``; any other refusal is one error naming the file."""
    warnings: list[str] = []
    refusal = None
    if sdf_file is not None:
        refusal = _drake_refusal(lambda parser: parser.AddModels(str(sdf_file)), workspace)
        if refusal is None:
            return warnings
    while True:
        if refusal is None:
            text = _without_own_pose(element, version, folder)
            refusal = _drake_refusal(lambda parser, t=text: parser.AddModelsFromString(t, "sdf"), workspace)
            if refusal is None:
                return warnings
            refusal = re.sub(r"^<+data-string>+:\d+: ", "", refusal)  # (a line of the text made here)
        found = _NOT_SDF.search(refusal)
        step = _at_xml_path(element, found.group(1)) if found else None
        if step is None:
            raise WorkspaceError(
                f"{sdf_file or doc.where(element)}: Drake's SDF parser refuses it: {refusal}"
            )
        parent, child = step
        where = doc.where(child)
        warnings.append(
            f"{where}: XML element <{child.tag}> under <{parent.tag}> is not defined in SDF; ignored"
        )
        parent.remove(child)
        refusal = None


def _without_own_pose(element: ET.Element, version: str, folder: Path) -> str:
    """:func:`model_text` of the model without its own ``<pose>`` (a world's ``relative_to``
    names frames outside the model; the loader places it)."""
    poses = [(i, child) for i, child in enumerate(element) if child.tag == "pose"]
    for _, pose in poses:
        element.remove(pose)
    try:
        return model_text(element, version, folder)
    finally:
        for i, pose in poses:
            element.insert(i, pose)


def _at_xml_path(model: ET.Element, path: str) -> tuple[ET.Element, ET.Element] | None:
    """(parent, element) at libsdformat's XML path (``/sdf/model[@name="m"]/link[@name="l"]/x``)
    in the model element (None: not there)."""
    steps = re.findall(r'/([^/\[]+)(?:\[@name="([^"]*)"\])?', path)
    if len(steps) < 3 or steps[0][0] != "sdf" or steps[1][0] != model.tag:
        return None
    parent = model
    for tag, name in steps[2:-1]:
        nested = next((c for c in parent if c.tag == tag and (not name or c.get("name") == name)), None)
        if nested is None:
            return None
        parent = nested
    tag, name = steps[-1]
    child = next((c for c in parent if c.tag == tag and (not name or c.get("name") == name)), None)
    return (parent, child) if child is not None else None


def model_config(model: WorldModel, workspace: Workspace) -> ModelConfig:
    """The world model as the scenario's typed model entry (loaded by Drake's Parser): its
    own SDF (geometry, joints, inertia, materials, friction), named as the world names it,
    at its pose in world, static as Gazebo has it (a static model's nested models too),
    its relative URIs resolved next to its file."""
    element = copy.deepcopy(model.element)
    for pose in element.findall("pose"):
        element.remove(pose)
    for old in element.findall("static"):
        element.remove(old)
    for nested in element.iter("model") if model.static else ():
        for old in nested.findall("static"):
            nested.remove(old)
        ET.SubElement(nested, "static").text = "true"
    text = model_text(element, model.version, model.folder or Path(model.where.split(":")[0]).parent)
    rpy = RollPitchYaw(model.X_WM.rotation()).vector()
    try:
        return model_from_text(
            text,
            model.where,
            workspace,
            name=model.name,
            xyz=tuple(float(v) for v in model.X_WM.translation()),  # type: ignore[arg-type]
            rpy=tuple(float(v) for v in rpy),  # type: ignore[arg-type]
            static=model.static,
        )
    except ConfigError as e:
        if isinstance(e, WorkspaceError):
            raise
        raise WorkspaceError(str(e)) from None
