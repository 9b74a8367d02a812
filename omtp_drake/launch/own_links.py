"""What a student added to a model that holds the course's pieces, loaded as it is written.

A spawned URDF in which :mod:`omtp_drake.launch.pieces` recognises course pieces (the
workcell, a bin, a pedestal, an arm, the break beam) gives those pieces their systems;
the cell builds them. Every *other* link of that URDF that carries geometry (a shelf
the student added to their workcell xacro, a box beside their bin) is not dropped: the
links are loaded with Drake's Parser exactly as the file writes them (their visuals,
collisions, inertia, Gazebo materials and friction), each fixed where the file's joint
chain puts it, as one model entry of the scenario (:class:`~omtp_drake.scenario.ModelConfig`,
the path ``--robot`` and the world's own models take).

A piece's links are the links named with its prefix (``robot1_``, ``vacuum_gripper1_``,
``bin_2_``, ``break_beam_``; the course's macros prefix every link they make) and the
workcell's ``workcell`` link. Only links that stand still are loaded: fixed to the
model's root link by fixed joints, or in a model Gazebo holds ``<static>``. A link the
student hung on a moving joint of a course piece (a camera mount on an arm's wrist) is
one warning line: the cell's arm is its own model, built from the catalogue.
"""

from __future__ import annotations

import copy
import xml.etree.ElementTree as ET
from collections.abc import Iterable

from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.launch.urdf_model import UrdfModel

#: The workcell's own link (the hall's mesh: the cell's floor and conveyor stand for it).
WORKCELL_LINK = "workcell"


def has_geometry(model: UrdfModel, link: str) -> bool:
    """Whether ``link`` carries a visual or a collision (else it is a frame only)."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    return element is not None and any(element.find(tag) is not None for tag in ("visual", "collision"))


def is_static(model: UrdfModel) -> bool:
    """Whether the model's ``<gazebo><static>`` holds it (Gazebo welds every link)."""
    for reference, element in model.gazebo:
        if not reference and (element.findtext("static") or "").strip().lower() in ("true", "1"):
            return True
    return False


def own_links(model: UrdfModel, prefixes: Iterable[str], where: str) -> tuple[list[str], list[str]]:
    """The links of ``model`` no recognised piece (``prefixes``) claims that carry geometry
    and stand still; and the warning lines of those that move (not loaded)."""
    prefixes = tuple(p for p in prefixes if p)
    mine = [
        link
        for link in model.links
        if link not in ("world", WORKCELL_LINK)
        and not link.startswith(prefixes)
        and has_geometry(model, link)
    ]
    still = set(model.links) if is_static(model) else set(model.static_links())
    warnings = [
        f"{where}: link {link!r} moves with a course piece's joints; not loaded "
        "(the cell builds the course's arms from its catalogue)"
        for link in mine
        if link not in still
    ]
    return [link for link in mine if link in still], warnings


def own_links_urdf(
    model: UrdfModel, links: list[str], X_WM: RigidTransform, joints: dict[str, float], name: str
) -> str:
    """A URDF of ``links`` as ``model`` writes them (with their ``<gazebo reference>``
    tags), each fixed to ``world`` at its pose: ``X_WM`` (the spawn pose) times the file's
    joint chain at ``joints`` (spawn_model's ``-J``; 0 for the others)."""
    root = model.root_element if model.root_element is not None else ET.Element("robot")
    X_ML = model.link_poses(joints)
    out = ET.Element("robot", name=name)
    ET.SubElement(out, "link", name="world")
    wanted = set(links)
    for element in root.findall("link"):
        link = element.get("name", "")
        if link not in wanted:
            continue
        out.append(copy.deepcopy(element))
        joint = ET.SubElement(out, "joint", name=f"{link}_fixed_to_world", type="fixed")
        ET.SubElement(joint, "parent", link="world")
        ET.SubElement(joint, "child", link=link)
        X_WL = X_WM @ X_ML[link]
        ET.SubElement(
            joint,
            "origin",
            xyz=" ".join(repr(float(v)) for v in X_WL.translation()),
            rpy=" ".join(repr(float(v)) for v in RollPitchYaw(X_WL.rotation()).vector()),
        )
    for element in root.findall("gazebo"):
        if element.get("reference", "") in wanted:
            out.append(copy.deepcopy(element))
    return ET.tostring(out, encoding="unicode")


def piece_urdf(model: UrdfModel, root_link: str, prefix: str, name: str) -> str:
    """A URDF of the piece at ``root_link``: the links below it named with ``prefix`` and
    the joints between them, as ``model`` writes them (``<gazebo reference>`` tags too)."""
    root = model.root_element if model.root_element is not None else ET.Element("robot")
    keep, stack = {root_link}, [root_link]
    while stack:
        parent = stack.pop()
        for joint in model.joints.values():
            if joint.parent == parent and joint.child.startswith(prefix) and joint.child not in keep:
                keep.add(joint.child)
                stack.append(joint.child)
    out = ET.Element("robot", name=name)
    for element in root:
        if element.tag == "link" and element.get("name") in keep:
            out.append(copy.deepcopy(element))
        elif element.tag == "joint" and element.get("name") in model.joints:
            joint = model.joints[element.get("name", "")]
            if joint.parent in keep and joint.child in keep:
                out.append(copy.deepcopy(element))
        elif element.tag == "gazebo" and element.get("reference") in keep:
            out.append(copy.deepcopy(element))
    return ET.tostring(out, encoding="unicode")


def bin_walls(model: UrdfModel, link: str) -> list[float] | None:
    """``[inner half length along x, along y, floor top, rim height]`` (m, in the link's
    frame) of a bin made of box collisions: the floor is the box under the link's origin,
    the walls the others (the nearest inner face on each axis); None when a collision is
    no box or there is no floor or no wall on each axis (a mesh bin:
    :mod:`~omtp_drake.launch.mesh_bins`)."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    collisions = element.findall("collision") if element is not None else []
    boxes = []
    for collision in collisions:
        box = collision.find("geometry/box")
        if box is None:
            return None
        try:
            size = [float(v) for v in box.get("size", "").split()]
            origin = collision.find("origin")
            xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        except ValueError:
            return None
        if len(size) != 3 or len(xyz) != 3 or len(rpy) != 3:
            return None
        X = RigidTransform(RollPitchYaw(rpy), xyz)
        corners = [
            X @ [sx * size[0] / 2, sy * size[1] / 2, sz * size[2] / 2]
            for sx in (-1, 1)
            for sy in (-1, 1)
            for sz in (-1, 1)
        ]
        boxes.append(
            (
                min(c[0] for c in corners),
                max(c[0] for c in corners),
                min(c[1] for c in corners),
                max(c[1] for c in corners),
                max(c[2] for c in corners),
            )
        )
    floors = [b for b in boxes if b[0] < 0 < b[1] and b[2] < 0 < b[3]]
    walls = [b for b in boxes if b not in floors]
    if not floors or not walls:
        return None
    # A wall on one side of the axis along x (or y) has an inner face across it.
    halves = [[min(abs(w[a]), abs(w[a + 1])) for w in walls if w[a] * w[a + 1] > 0] for a in (0, 2)]
    if not all(halves):
        return None
    inner = [min(h) for h in halves]
    return [round(float(v), 9) for v in (*inner, max(f[4] for f in floors), max(b[4] for b in boxes))]
