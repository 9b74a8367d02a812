"""Models from description files in a plant: the scenario's ``models``, as Gazebo spawns them.

:func:`add_described_models` adds each :class:`~omtp_drake.scenario.ModelConfig` with
Drake's Parser, its ``package://`` and ``model://`` URIs resolved in the model's
packages, and places it as ``spawn_model`` does: a URDF whose root is a ``world``
link is fixed by its own joint, moved by the model's pose; any other model starts at
the pose (welded there when ``static``). With ``gazebo_look`` (what the simulation
shows, as Gazebo does) each link's Gazebo material colours its visuals and its
``mu1``/``mu2`` set its collisions' friction; without it (the ``view`` command, as
rviz does) the URDF's own colours stay. Every link becomes a body, hence a tf frame.
"""

from __future__ import annotations

import contextlib
import logging
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from typing import Optional

from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import FixedOffsetFrame, ModelInstanceIndex

from omtp_drake.assets import DRAKE_NS, drake_ready_meshes
from omtp_drake.errors import WorkspaceError
from omtp_drake.scenario import ModelConfig

_log = logging.getLogger(__name__)

ET.register_namespace("drake", DRAKE_NS)

#: Diffuse colours of Gazebo's stock materials (``gazebo.material``), RGBA.
GAZEBO_COLORS: dict[str, tuple[float, float, float, float]] = {
    "Gazebo/White": (1.0, 1.0, 1.0, 1.0),
    "Gazebo/Grey": (0.7, 0.7, 0.7, 1.0),
    "Gazebo/DarkGrey": (0.175, 0.175, 0.175, 1.0),
    "Gazebo/Black": (0.0, 0.0, 0.0, 1.0),
    "Gazebo/FlatBlack": (0.1, 0.1, 0.1, 1.0),
    "Gazebo/RedBright": (0.87, 0.26, 0.07, 1.0),
    "Gazebo/SkyBlue": (0.0, 0.0, 1.0, 1.0),
    "Gazebo/ZincYellow": (0.9725, 0.9529, 0.2078, 1.0),
    "Gazebo/Gold": (0.8, 0.64869, 0.120759, 1.0),
    "Gazebo/Red": (1.0, 0.0, 0.0, 1.0),
    "Gazebo/Green": (0.0, 1.0, 0.0, 1.0),
    "Gazebo/Blue": (0.0, 0.0, 1.0, 1.0),
    "Gazebo/Yellow": (1.0, 1.0, 0.0, 1.0),
    "Gazebo/Orange": (1.0, 0.5088, 0.0468, 1.0),
    "Gazebo/Purple": (1.0, 0.0, 1.0, 1.0),
    "Gazebo/Turquoise": (0.0, 1.0, 1.0, 1.0),
}


def add_described_models(
    parser: Parser, models: list[ModelConfig], *, gazebo_look: bool = True
) -> dict[str, ModelInstanceIndex]:
    """Adds ``models`` to the parser's plant (not finalized); returns name -> instance.

    Raises:
        WorkspaceError: a description Drake refuses (the message names the file and
            the parser's first line).
    """
    plant = parser.plant()
    instances: dict[str, ModelInstanceIndex] = {}
    for model in models:
        text = prepared_description(model, gazebo_look=gazebo_look)
        model_parser = Parser(plant)
        package_map = model_parser.package_map()
        for name, folder in model.packages.items():
            if not package_map.Contains(name):
                package_map.Add(name, folder)
        try:
            with drake_errors() as errors:
                added = model_parser.AddModelsFromString(text, model.format)
        except (RuntimeError, ValueError) as e:  # (libsdformat's stoi of a bad version: ValueError)
            first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
            raise WorkspaceError(f"{model.file}: Drake's parser refuses it: {first}") from None
        if errors:
            raise WorkspaceError(f"{model.file}: Drake's parser refuses it: {errors[0]}")
        # An SDF model's nested models are instances of their own (``model::nested``).
        tops = [i for i in added if plant.GetModelInstanceName(i) == model.name]
        if len(tops) != 1:
            raise WorkspaceError(f"{model.file}: it holds more than one model; give one per file")
        instance = tops[0]
        instances[model.name] = instance
        _place(plant, model, instance)
        _add_model_frame(plant, model, instance)
    return instances


@contextlib.contextmanager
def drake_errors() -> Iterator[list[str]]:
    """The first lines of the errors Drake logs (and does not raise) while the block runs,
    kept from the log (they become the caller's one error line):
    libsdformat's "Unable to set value [abc ...] for key [pose]" is logged and the element
    left at its default, where Gazebo's sdformat refuses the file."""
    found: list[str] = []

    def collect(record: logging.LogRecord) -> bool:
        """Keeps an error (the caller raises it as one line); lets the rest through."""
        if record.levelno < logging.ERROR:
            return True
        text = record.getMessage().strip()
        found.append(text.splitlines()[0] if text else "an error")
        return False

    drake_log = logging.getLogger("drake")
    drake_log.addFilter(collect)
    try:
        yield found
    finally:
        drake_log.removeFilter(collect)


def model_pose(model: ModelConfig) -> RigidTransform:
    """``X_WM``: the model's pose in the world."""
    return RigidTransform(RollPitchYaw(model.rpy), model.xyz)


def prepared_description(model: ModelConfig, *, gazebo_look: bool) -> str:
    """The description to parse: named as the model, its meshes as Drake reads them
    (:func:`~omtp_drake.assets.drake_ready_meshes`), a ``world`` link's joints moved by
    the model's pose, and (``gazebo_look``) the Gazebo materials and friction applied."""
    root = ET.fromstring(model.description)
    drake_ready_meshes(root, file=model.file, packages=model.packages, open_links=model.open_links)
    if model.format == "sdf":
        first = root.find("model")
        if first is not None:
            # The model's pose in world moves the file's own, as spawn_model's -x ... do (a
            # world's model entry holds its whole pose); Drake places the links from it
            # (relative_to included) and welds a static model.
            first.set("name", model.name)
            X_WM = model_pose(model)
            for old in first.findall("pose"):
                X_WM = X_WM @ _sdf_pose(old.text)
                first.remove(old)
            pose = ET.Element("pose")
            xyz, rpy = X_WM.translation(), RollPitchYaw(X_WM.rotation()).vector()
            pose.text = " ".join(repr(float(v)) for v in [*xyz, *rpy])
            first.insert(0, pose)
            links = list(first.iter("link"))
            if gazebo_look and not model.static and len(links) == 1:
                _add_corner_supports(links[0], "sdf")
        return ET.tostring(root, encoding="unicode")
    root.set("name", model.name)
    X_WM = model_pose(model)
    if not X_WM.IsExactlyIdentity():
        for joint in root.findall("joint"):
            parent = joint.find("parent")
            if parent is not None and parent.get("link") == "world":
                _set_origin(joint, X_WM @ _origin(joint))
    if gazebo_look:
        _apply_gazebo_tags(root, model)
        links = [link for link in root.findall("link") if link.get("name") != "world"]
        if not model.static and len(links) == 1 and not root.findall("joint"):
            _add_corner_supports(links[0], "urdf")
    return ET.tostring(root, encoding="unicode")


#: Radius (m) of the spheres at a box collision's corners.
CORNER_RADIUS = 0.001


def _add_corner_supports(link: ET.Element, format: str) -> None:
    """Eight 1 mm spheres at the corners of each box collision of a free one-link model (a
    box, a cube: what lies on tables and shelves), beside the box. Drake's point contact
    gives a box on a flat surface one contact point (it tilts and sinks); Gazebo's ODE
    gives it its face's corners. The cell's own parts rest the same way
    (``models/part.urdf.xacro``)."""
    for collision in list(link.findall("collision")):
        box = collision.find("geometry/box")
        size = (box.findtext("size") if format == "sdf" else box.get("size")) if box is not None else None
        try:
            half = [float(v) / 2 for v in (size or "").split()]
        except ValueError:
            continue
        if len(half) != 3:
            continue
        X_LC = _sdf_pose(collision.findtext("pose")) if format == "sdf" else _origin(collision)
        name = collision.get("name", "collision")
        corners = [(sx, sy, sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
        for k, corner in enumerate(corners):
            X_LS = X_LC @ RigidTransform([c * h for c, h in zip(corner, half)])
            sphere = ET.SubElement(link, "collision", name=f"{name}_corner_{k}")
            if format == "sdf":
                xyz, rpy = X_LS.translation(), RollPitchYaw(X_LS.rotation()).vector()
                ET.SubElement(sphere, "pose").text = " ".join(repr(float(v)) for v in [*xyz, *rpy])
                shape = ET.SubElement(ET.SubElement(sphere, "geometry"), "sphere")
                ET.SubElement(shape, "radius").text = str(CORNER_RADIUS)
            else:
                _set_origin(sphere, X_LS)
                ET.SubElement(ET.SubElement(sphere, "geometry"), "sphere", radius=str(CORNER_RADIUS))


def _sdf_pose(text: str | None) -> RigidTransform:
    values = [float(v) for v in (text or "0 0 0 0 0 0").split()]
    return RigidTransform(RollPitchYaw(values[3:6]), values[:3])


def _origin(element: ET.Element) -> RigidTransform:
    origin = element.find("origin")
    if origin is None:
        return RigidTransform()
    xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()]
    rpy = [float(v) for v in origin.get("rpy", "0 0 0").split()]
    return RigidTransform(RollPitchYaw(rpy), xyz)


def _set_origin(element: ET.Element, X: RigidTransform) -> None:
    origin = element.find("origin")
    if origin is None:
        origin = ET.SubElement(element, "origin")
    origin.set("xyz", " ".join(repr(float(v)) for v in X.translation()))
    origin.set("rpy", " ".join(repr(float(v)) for v in RollPitchYaw(X.rotation()).vector()))


def _apply_gazebo_tags(root: ET.Element, model: ModelConfig) -> None:
    links = {link.get("name"): link for link in root.findall("link")}
    for material in model.gazebo.materials:
        rgba = GAZEBO_COLORS.get(material.name)
        link = links.get(material.link)
        if rgba is None or link is None:
            _log.warning(
                "%s: Gazebo material %r on %r not shown (known: %s)",
                model.file,
                material.name,
                material.link,
                ", ".join(GAZEBO_COLORS),
            )
            continue
        for visual in link.findall("visual"):
            for old in visual.findall("material"):
                visual.remove(old)
            element = ET.SubElement(visual, "material", name=material.name.replace("/", "_"))
            ET.SubElement(element, "color", rgba=" ".join(str(c) for c in rgba))
    for friction in model.gazebo.frictions:
        link = links.get(friction.link)
        if link is None:
            continue
        for collision in link.findall("collision"):
            props = ET.SubElement(collision, f"{{{DRAKE_NS}}}proximity_properties")
            ET.SubElement(props, f"{{{DRAKE_NS}}}mu_dynamic", value=str(min(friction.mu1, friction.mu2)))
            ET.SubElement(props, f"{{{DRAKE_NS}}}mu_static", value=str(max(friction.mu1, friction.mu2)))


def _place(plant: MultibodyPlant, model: ModelConfig, instance: ModelInstanceIndex) -> None:
    """A model not fixed by its own description: its root link welded at the model's pose
    when static, else starting there (floating); one hung on a ``parent`` frame of the
    cell, welded there (:func:`_hang`). An SDF ``<static>`` model Drake welds itself."""
    root = ET.fromstring(model.description)
    if model.parent:
        _hang(plant, model, instance, root)
        return
    base = _root_link(root, model.format)
    if base is None:
        return
    name, X_ML = base
    body = plant.GetBodyByName(name, instance)
    sdf_model = root.find("model")  # (None for a URDF)
    X_MF = _sdf_pose(sdf_model.findtext("pose") if sdf_model is not None else None)  # the file's own pose
    X_WL = model_pose(model) @ X_MF @ X_ML
    if model.static:
        plant.WeldFrames(plant.world_frame(), body.body_frame(), X_WL)
    elif model.format == "urdf":  # (an SDF model's free bodies Drake placed from its <pose>)
        plant.SetDefaultFloatingBaseBodyPose(body, X_WL)


def _hang(plant: MultibodyPlant, model: ModelConfig, instance: ModelInstanceIndex, root: ET.Element) -> None:
    """Each link of ``model`` no joint moves, welded to its ``parent`` frame of the cell
    (a link of a course piece: they move with it) at the model's pose in that frame."""
    if not plant.HasFrameNamed(model.parent):
        raise WorkspaceError(
            f"{model.file}: model {model.name!r} hangs on {model.parent!r}; the cell has no such frame"
        )
    parent = plant.GetFrameByName(model.parent)
    element = root.find("model") if model.format == "sdf" else root
    if element is None:
        return
    X_PM = model_pose(model) @ _sdf_pose(element.findtext("pose") if model.format == "sdf" else None)
    children = {c.get("link") for c in element.findall("joint/child")}  # (URDF)
    children |= {(c.text or "").strip() for c in element.findall("joint/child")}  # (SDF)
    for link in element.findall("link"):
        name = link.get("name", "")
        if name not in children:
            X_ML = _sdf_pose(link.findtext("pose")) if model.format == "sdf" else RigidTransform()
            plant.WeldFrames(parent, plant.GetBodyByName(name, instance).body_frame(), X_PM @ X_ML)


def _add_model_frame(plant: MultibodyPlant, model: ModelConfig, instance: ModelInstanceIndex) -> None:
    """An SDF model's frame (Gazebo's model pose, what ``get_model_state`` reports) as a
    frame named as the model, unless one of its own frames has that name."""
    if model.format != "sdf" or plant.HasFrameNamed(model.name, instance):
        return
    frame = plant.GetFrameByName("__model__", instance)
    X_BM = frame.GetFixedPoseInBodyFrame()
    plant.AddFrame(FixedOffsetFrame(model.name, frame.body().body_frame(), X_BM, instance))


def _root_link(root: ET.Element, format: str) -> Optional[tuple[str, RigidTransform]]:
    """The link no joint moves and its pose in the model (None: none, or fixed already:
    a URDF ``world`` link, a link an SDF joint ties to ``world``, an SDF static model)."""
    if format == "urdf":
        links, children = root.findall("link"), {c.get("link") for c in root.findall("joint/child")}
        if any(link.get("name") == "world" for link in links):
            return None
        free = [link.get("name", "") for link in links if link.get("name") not in children]
        return (free[0], RigidTransform()) if free else None
    model = root.find("model")
    if model is None or (model.findtext("static") or "").strip() in ("true", "1"):
        return None
    joints = model.findall("joint")
    if any((j.findtext("parent") or "").strip() == "world" for j in joints):
        return None
    children = {(j.findtext("child") or "").strip() for j in joints}
    for link in model.findall("link"):
        if link.get("name") not in children:
            values = [float(v) for v in (link.findtext("pose") or "0 0 0 0 0 0").split()]
            return link.get("name", ""), RigidTransform(RollPitchYaw(values[3:6]), values[:3])
    return None
