"""What a student added to a course model of their world, loaded as it is written.

The cell builds the conveyor, the deletion wall and the logical cameras from its catalogue
where the world's model (recognised by its plugin, :mod:`omtp_drake.launch.world_pieces`)
puts them. What the student added to such a ``<model>`` is not dropped: a link the
course's model does not have (a guard rail beside the belt, a lens hood on a camera), a
visual or collision the course's link does not have (a bigger plate on the deletion wall),
and a camera link's own housing (the course's ``camera.dae`` or the student's) are one
model entry of the scenario (:class:`~omtp_drake.scenario.ModelConfig`, loaded by Drake's
Parser as the file writes them: geometry, inertia, materials, friction), named
``<model>_own``, welded where the file puts them to the cell's body of the piece
(``ModelConfig.parent``: ``conveyor_base``, ``deletion_wall``, ``<camera>_frame``), so
they are part of its Gazebo model (what the logical cameras list).

They are loaded when they stand still in Gazebo: a link of a ``<static>`` model (the
wall, the conveyor's ``conveyor_belt_fixed``), the link holding a logical camera's sensor
(the course's camera model floats without gravity; the cell holds it where the world puts
it), or one a ``fixed`` joint holds to such a link. One that would move (a free link of
the conveyor's top model, a link on a moving joint, geometry on the moving ``belt``) is
one warning line: the cell's belt is its own body, and it adds no joints to the course's
pieces.
"""

from __future__ import annotations

import copy
import xml.etree.ElementTree as ET
from pathlib import Path

from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.launch.sdf_world import WorldModel, model_text, sdf_pose
from omtp_drake.scenario import ModelConfig
from omtp_drake.scenario.models import model_from_text
from omtp_drake.workspace import Workspace

#: The links of the course's models (``omtp_gazebo/models/*/model.sdf``), by the plugin
#: that makes them a piece, with the visuals and collisions the course gives them: the
#: catalogue builds these.
COURSE_LINKS: dict[str, dict[str, tuple[str, ...]]] = {
    "conveyor": {
        "conveyor_belt_fixed::link": (),
        "conveyor_belt_moving::belt": ("belt_collision", "belt_visual"),
    },
    "deletion_wall": {"sensing_link": ("collision", "visual")},
}
_GEOMETRY = ("visual", "collision")
#: The course's geometry of a logical camera link the cell builds: none. Its ``camera.dae``
#: visual and collision (``logical_camera*/model.sdf``), or what the student wrote in
#: their place, are loaded as written; the cell draws no housing of its own there.
_CAMERA_GEOMETRY: tuple[str, ...] = ()


def additions(
    model: WorldModel, kind: str | None, workspace: Workspace, body: tuple[str, RigidTransform] | None
) -> tuple[ModelConfig | None, list[str]]:
    """The model entry of what the student added to ``model`` (a course piece of ``kind``;
    None: nothing), hung on ``body`` (the cell's body of the piece and its pose in world),
    and the warning lines of what is not loaded (see module doc)."""
    links = _links(model.element, "", RigidTransform(), model.static)
    course = _course_links(kind, links)
    if course is None or body is None:
        return None, []
    still = {path for path, (_, _, static) in links.items() if static}
    if kind == "logical_camera":
        still |= set(course)  # (the cell holds the camera where the world puts it)
    still |= _held(model.element, still)
    out = ET.Element("model", name=f"{model.name}_own")  # (no <static>: the cell welds it to ``body``)
    warnings = []
    for path, (link, X_ML, _) in links.items():
        own = link.get("name", "")
        if path in course:
            warnings += changed_lines(model, kind, path, link, X_ML)
            extras = [c for c in link if c.tag in _GEOMETRY and c.get("name") not in course[path]]
            if not extras:
                continue
            kept = ET.Element("link", name=f"{path.replace('::', '_')}_own")
            kept.extend(copy.deepcopy(c) for c in extras)
            what = f"{', '.join(c.get('name', '') for c in extras)} of the course's link {path!r}"
        else:
            kept = copy.deepcopy(link)
            for pose in kept.findall("pose"):
                kept.remove(pose)
            what = f"link {path!r}"
        if path not in still:
            warnings.append(
                f"{model.where}: {what} of model {model.name!r} moves (not static, no fixed joint to a "
                "static link); not loaded (the cell builds the course's moving parts from its catalogue)"
            )
            continue
        kept.set("name", kept.get("name") or own)
        xyz, rpy = X_ML.translation(), RollPitchYaw(X_ML.rotation()).vector()
        pose = ET.Element("pose")
        pose.text = " ".join(repr(float(v)) for v in [*xyz, *rpy])
        kept.insert(0, pose)
        out.append(kept)
    if out.find("link") is None:
        return None, warnings
    folder = model.folder or Path(model.where.split(":")[0]).parent
    parent, X_WP = body
    X_PM = X_WP.inverse() @ model.X_WM
    xyz, rpy = X_PM.translation(), RollPitchYaw(X_PM.rotation()).vector()
    entry = model_from_text(
        model_text(out, model.version, folder),
        model.where,
        workspace,
        name=out.get("name", ""),
        xyz=(float(xyz[0]), float(xyz[1]), float(xyz[2])),
        rpy=(float(rpy[0]), float(rpy[1]), float(rpy[2])),
        static=True,
    )
    entry.parent = parent
    return entry, warnings


#: The cell's own geometry of the course's named elements where it acts (the catalogue's):
#: piece -> (link, element name) -> its box (m) and pose in the piece's model; for the belt
#: what a part feels: its footprint, and its top (the pose's z) rather than its thickness.
CELL_GEOMETRY: dict[str, dict[tuple[str, str], tuple[tuple[float, ...], RigidTransform]]] = {
    "deletion_wall": {
        ("sensing_link", "collision"): ((0.1, 1.0, 1.0), RigidTransform()),
        ("sensing_link", "visual"): ((0.1, 1.0, 1.0), RigidTransform()),
    },
    "conveyor": {
        ("conveyor_belt_moving::belt", "belt_collision"): ((10.0, 0.6), RigidTransform([5.0, 0.0, 0.92]))
    },
}
_TOL = 1e-3


def belt_box(link: ET.Element, where: str) -> tuple[tuple[float, float, float], RigidTransform] | None:
    """The size and pose in ``link`` of the conveyor's ``belt_collision`` when it is a box
    lying along the link's x (the way the plugin moves the link, so its parts ride it
    lengthwise): the cell's belt is then as long, wide and high as this box, where it
    is. None for any other shape or a turned box (the cell keeps its own belt)."""
    collision = link.find("collision[@name='belt_collision']")
    size_text = collision.findtext("geometry/box/size") if collision is not None else None
    if collision is None or size_text is None:
        return None
    try:
        size = tuple(float(v) for v in size_text.split())
    except ValueError:
        return None
    X_LG = sdf_pose(collision.findtext("pose"), where)
    if len(size) != 3 or not X_LG.rotation().IsNearlyIdentity(_TOL):
        return None
    return (size[0], size[1], size[2]), X_LG


def changed_lines(
    model: WorldModel, kind: str | None, path: str, link: ET.Element, X_ML: RigidTransform
) -> list[str]:
    """One line for each of the course's elements of ``link`` (at ``X_ML`` in the model)
    that the student changed from the cell's (:data:`CELL_GEOMETRY`): the cell's piece
    keeps its own, since its plugin's behaviour is on the cell's body. (A belt box lying
    along the belt, :func:`belt_box`, is no change: the cell's belt is made as written.)"""
    lines = []
    for element in link:
        cell = CELL_GEOMETRY.get(kind or "", {}).get((path, element.get("name", "")))
        if element.tag not in _GEOMETRY or cell is None:
            continue
        if kind == "conveyor" and belt_box(link, model.where_of(element)) is not None:
            continue
        size_text = element.findtext("geometry/box/size")
        try:
            size = tuple(float(v) for v in (size_text or "").split())
        except ValueError:
            size = ()
        X_MG = X_ML @ sdf_pose(element.findtext("pose"), model.where_of(element))
        if _as_cell(size, X_MG, cell):
            continue
        shape = f"box {size_text.strip()}" if size_text else "no box"
        xyz = " ".join(f"{v:g}" for v in X_MG.translation())
        cell_size = " x ".join(f"{v:g}" for v in cell[0])
        lines.append(
            f"{model.where_of(element)}: <{element.tag} name={element.get('name')!r}> of the course's link "
            f"{path!r} in model {model.name!r} is {shape} at {xyz}; the cell's {kind} is its own "
            f"({cell_size} at {' '.join(f'{v:g}' for v in cell[1].translation())}) and keeps it: "
            "not loaded (the plugin's behaviour is on the cell's body)"
        )
    return lines


def wall_changed(model: WorldModel) -> bool:
    """Whether the student changed the course's deletion wall (a collision or visual of
    its ``sensing_link`` is not the cell's box): then the wall is loaded as they wrote it."""
    links = _links(model.element, "", RigidTransform(), model.static)
    return any(
        changed_lines(model, "deletion_wall", path, link, X_ML)
        for path, (link, X_ML, _) in links.items()
        if path in COURSE_LINKS["deletion_wall"]
    )


def _as_cell(size: tuple[float, ...], X_MG: RigidTransform, cell) -> bool:
    """Whether a box of ``size`` at ``X_MG`` is the cell's (:data:`CELL_GEOMETRY`)."""
    cell_size, X_MC = cell
    if len(size) != 3 or not (X_MG.rotation().inverse() @ X_MC.rotation()).IsNearlyIdentity(_TOL):
        return False
    p, c = X_MG.translation(), X_MC.translation()
    if len(cell_size) == 2:  # the belt: footprint, and the top where the cell's is
        top = p[2] + size[2] / 2
        return (
            max(abs(size[0] - cell_size[0]), abs(size[1] - cell_size[1]), abs(top - c[2])) < _TOL
            and max(abs(p[0] - c[0]), abs(p[1] - c[1])) < _TOL
        )
    return max(abs(a - b) for a, b in zip(size, cell_size)) < _TOL and max(abs(p - c)) < _TOL


def _course_links(
    kind: str | None, links: dict[str, tuple[ET.Element, RigidTransform, bool]]
) -> dict[str, tuple[str, ...]] | None:
    """The course's links of a piece of ``kind`` and their course geometry (None: no piece
    the cell builds): a logical camera's is the link holding its ``logical_camera`` sensor,
    whose every visual and collision (the course's ``camera.dae`` housing, or the
    student's in its place) is loaded as written."""
    if kind == "logical_camera":
        return {
            path: _CAMERA_GEOMETRY
            for path, (link, _, _) in links.items()
            if any(s.get("type") == "logical_camera" for s in link.findall("sensor"))
        }
    return COURSE_LINKS.get(kind or "")


def _links(
    element: ET.Element, prefix: str, X_MN: RigidTransform, static: bool
) -> dict[str, tuple[ET.Element, RigidTransform, bool]]:
    """``path -> (link, X_ML, static)`` of the model ``element``'s links, its nested
    models' too (``nested::link``), posed in the top model's frame."""
    found = {}
    for link in element.findall("link"):
        X_NL = sdf_pose(link.findtext("pose"), "")
        found[prefix + link.get("name", "")] = (link, X_MN @ X_NL, static)
    for nested in element.findall("model"):
        X_MC = X_MN @ sdf_pose(nested.findtext("pose"), "")
        nested_static = static or (nested.findtext("static") or "").strip() in ("true", "1")
        found.update(_links(nested, f"{prefix}{nested.get('name', '')}::", X_MC, nested_static))
    return found


def _held(element: ET.Element, still: set[str]) -> set[str]:
    """The links a ``fixed`` joint of the top model holds (through others) to a link in ``still``."""
    joints = [
        ((j.findtext("parent") or "").strip(), (j.findtext("child") or "").strip())
        for j in element.findall("joint")
        if j.get("type") == "fixed"
    ]
    held: set[str] = set()
    grew = True
    while grew:
        grew = False
        for parent, child in joints:
            if (parent in still or parent in held) and child not in still | held:
                held.add(child)
                grew = True
    return held
