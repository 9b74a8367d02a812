"""What a student added to a model that holds the course's pieces, loaded as it is written.

A spawned URDF in which :mod:`omtp_drake.launch.pieces` recognises course pieces (the
workcell, a bin, a pedestal, an arm, the break beam) gives those pieces their systems;
the cell builds them. Every *other* link of that URDF that carries geometry (a shelf
the student added to their workcell xacro, a box beside their bin) is not dropped: the
links are loaded with Drake's Parser exactly as the file writes them (their visuals,
collisions, inertia, Gazebo materials and friction), each fixed where the file's joint
chain puts it, as one model entry of the scenario (:class:`~omtp_drake.scenario.ModelConfig`,
the path ``--robot`` and the world's own models take).

A piece's links (:class:`Claims`) are those the course's macros give it, with its prefix
(an arm's ``robot1_base_link`` ... ``robot1_tool0``, a gripper's ``vacuum_gripper1_base_link``
and ``_suction_cup``, ``robot1_pedestal_link``, the beam's ``break_beam_base_link``,
``_optical_link``, ``_world_interface``; every ``bin_2_`` link of a bin, which is loaded
with them) and the workcell's ``workcell`` link: a ``robot1_camera_link`` of the student's
is theirs. Links that stand still (fixed to the model's root link by
fixed joints, or in a model Gazebo holds ``<static>``) are fixed to the world. Links the
student hung by fixed joints on a link of a course piece that moves (a camera mount on an
arm's wrist, a plate on the vacuum gripper) are a :class:`Mount`: loaded as written and
welded to the cell's body of that link (the cell builds the arm and gripper from its
catalogue, with the course's link names) at the pose the file's joints give, so they move
with it and weigh on it. A link on a moving joint of its own below a piece is one warning
line (the cell adds no joints to its arms).
"""

from __future__ import annotations

import copy
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.launch.urdf_model import UrdfJoint, UrdfModel

#: The workcell's own link (the hall's mesh: the cell's floor and conveyor stand for it).
WORKCELL_LINK = "workcell"
#: The course's own meshes (``ur_description``'s, ``omtp_support``'s): a visual or collision
#: with one of them in a piece's link is the course's.
_COURSE_MESHES = ("ur_description/meshes/", "omtp_support/meshes/")
#: The pieces' links the course's files give no visual and no collision (ur_description's
#: frames, the break beam's): whatever such a link of the student's holds is theirs.
_BARE_LINKS = ("tool0", "flange", "base", "world_interface", "optical_link")


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


@dataclass(frozen=True)
class Claims:
    """The links the recognised pieces take as their own: by name (the links the course's
    macros give an arm, a gripper, a pedestal, the beam) or by prefix (a bin's: the bin is
    loaded with all of them); ``world`` and the workcell's link always."""

    names: frozenset[str] = frozenset()
    prefixes: tuple[str, ...] = ()

    def __contains__(self, link: object) -> bool:
        return isinstance(link, str) and (
            link in ("world", WORKCELL_LINK) or link in self.names or link.startswith(self.prefixes)
        )


def _as_claims(claims: Claims | Iterable[str]) -> Claims:
    """``claims`` itself, or the claims of the link prefixes ``claims``."""
    return claims if isinstance(claims, Claims) else Claims(prefixes=tuple(p for p in claims if p))


def own_links(model: UrdfModel, claims: Claims | Iterable[str], where: str) -> tuple[list[str], list[str]]:
    """The links of ``model`` no recognised piece claims (``claims``, or link prefixes)
    that carry geometry and stand still; and the warning lines of those on a moving joint
    of their own (the links that move with a piece are :func:`mounts`)."""
    prefixes = _as_claims(claims)
    mine = [link for link in model.links if not _claimed(link, prefixes) and has_geometry(model, link)]
    still = set(model.links) if is_static(model) else set(model.static_links())
    mounted = {link for mount in mounts(model, prefixes) for link in mount.links}
    warnings = [
        f"{where}: link {link!r} moves on a joint of its own ({_own_joint(model, link, prefixes)!r}); "
        "not loaded (the cell adds no joints to the course's pieces)"
        for link in mine
        if link not in still and link not in mounted
    ]
    return [link for link in mine if link in still], warnings


def _claimed(link: str, claims: Claims) -> bool:
    return link in claims


def _parent_joint(model: UrdfModel, link: str) -> UrdfJoint | None:
    return next((j for j in model.joints.values() if j.child == link), None)


def _own_joint(model: UrdfModel, link: str, prefixes: Claims) -> str:
    """The nearest moving joint above ``link`` that is not a piece's own."""
    joint = _parent_joint(model, link)
    while joint is not None and joint.type == "fixed" and not _claimed(joint.parent, prefixes):
        joint = _parent_joint(model, joint.parent)
    return joint.name if joint is not None else ""


@dataclass(frozen=True)
class Mount:
    """Links a student hung by fixed joints on ``parent``, a moving link of a course piece."""

    root: str  # the topmost of them (its joint's parent is ``parent``)
    parent: str
    links: tuple[str, ...]  # ``root`` and the links fixed below it, in the file's order
    X_PR: RigidTransform  # ``root`` in ``parent``, from the file's joint


def mounts(model: UrdfModel, claims: Claims | Iterable[str]) -> list[Mount]:
    """The student's links fixed (through fixed joints) to a link of a course piece
    (``claims``, or link prefixes) that moves, one :class:`Mount` per link hung on it."""
    prefixes = _as_claims(claims)
    still = set(model.links) if is_static(model) else set(model.static_links())
    found = []
    for joint in model.joints.values():
        if joint.type != "fixed" or joint.parent in still or not _claimed(joint.parent, prefixes):
            continue
        if _claimed(joint.child, prefixes):
            continue
        below, stack = {joint.child}, [joint.child]
        while stack:
            parent = stack.pop()
            for j in model.joints.values():
                if j.parent == parent and j.type == "fixed" and not _claimed(j.child, prefixes):
                    below.add(j.child)
                    stack.append(j.child)
        links = tuple(link for link in model.links if link in below)
        found.append(Mount(joint.child, joint.parent, links, joint.X_PJ))
    return found


def mount_urdf(model: UrdfModel, mount: Mount, name: str) -> str:
    """A URDF of ``mount``'s links as ``model`` writes them, the fixed joints between them
    and their ``<gazebo reference>`` tags (its root is welded to the piece by the cell)."""
    return _subset_urdf(model, set(mount.links), name)


def _subset_urdf(model: UrdfModel, wanted: set[str], name: str) -> str:
    """A URDF named ``name`` of the links ``wanted`` as ``model`` writes them, the joints
    between them and their ``<gazebo reference>`` tags, in the file's order."""
    root = model.root_element if model.root_element is not None else ET.Element("robot")
    out = ET.Element("robot", name=name)
    for element in root:
        if element.tag == "link" and element.get("name") in wanted:
            out.append(copy.deepcopy(element))
        elif element.tag == "joint" and element.get("name") in model.joints:
            joint = model.joints[element.get("name", "")]
            if joint.parent in wanted and joint.child in wanted:
                out.append(copy.deepcopy(element))
        elif element.tag == "gazebo" and element.get("reference") in wanted:
            out.append(copy.deepcopy(element))
    return ET.tostring(out, encoding="unicode")


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
    keep, stack = {root_link}, [root_link]
    while stack:
        parent = stack.pop()
        for joint in model.joints.values():
            if joint.parent == parent and joint.child.startswith(prefix) and joint.child not in keep:
                keep.add(joint.child)
                stack.append(joint.child)
    return _subset_urdf(model, keep, name)


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


def inner_additions(
    model: UrdfModel, links: Iterable[str], meshed: Mapping[str, tuple[str, str]] | None = None
) -> dict[str, list[ET.Element]]:
    """The visuals and collisions a student added inside the course's ``links`` of
    ``model`` (URDF's are unnamed, so told apart by the course's files' content): the
    course's files give each of these links (``ur_description``'s, the vacuum gripper's, the
    beam's) at most one visual and one collision, so beyond one of a kind the ones that are
    not the course's mesh (:data:`_COURSE_MESHES`) are the student's, and with none of the
    course's mesh, all but the first; in a link the course gives none (:data:`_BARE_LINKS`),
    every one; in the workcell's hall link (the course's gives it only its meshes), every
    one that is not the course's mesh. In a link of ``meshed`` (an arm's body, mapped to its
    unprefixed name and UR model: the course's ``ur_description`` gives each a visual and a
    collision mesh), every one that is not that link's own mesh as the course writes it
    (:func:`is_arm_mesh`): a kind with none of it was replaced (:func:`replaced_kinds`)."""
    root = model.root_element
    meshed = meshed or {}
    out: dict[str, list[ET.Element]] = {}
    for link in links:
        element = root.find(f"link[@name='{link}']") if root is not None else None
        if element is None:
            continue
        if link.endswith(_BARE_LINKS) or link == WORKCELL_LINK:
            extras = [
                e
                for e in element
                if e.tag in ("visual", "collision") and not (link == WORKCELL_LINK and _is_course_mesh(e))
            ]
            if extras:
                out[link] = extras
            continue
        extras = []
        for tag in ("visual", "collision"):
            found = element.findall(tag)
            if link in meshed:
                extras += [e for e in found if not is_arm_mesh(e, *meshed[link])]
                continue
            if len(found) < 2:
                continue
            course = [e for e in found if _is_course_mesh(e)] or found[:1]
            extras += [e for e in found if not any(e is c for c in course[:1])]
        if extras:
            out[link] = extras
    return out


def replaced_kinds(model: UrdfModel, link: str, arm_link: str, ur_model: str) -> list[str]:
    """The kinds (``visual``, ``collision``) of which the arm's ``link`` (``arm_link``
    unprefixed, of a ``ur_model`` arm) holds elements but none its own course mesh
    (:func:`is_arm_mesh`): the student replaced the course's geometry of that kind (a
    shape, another mesh file, the mesh scaled)."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    if element is None:
        return []
    return [
        tag
        for tag in ("visual", "collision")
        if element.findall(tag) and not any(is_arm_mesh(e, arm_link, ur_model) for e in element.findall(tag))
    ]


#: ur_description's mesh of each arm link: ``meshes/<model>/{visual,collision}/<name>.*``.
UR_LINK_MESHES = {
    "base_link": "base",
    "shoulder_link": "shoulder",
    "upper_arm_link": "upperarm",
    "forearm_link": "forearm",
    "wrist_1_link": "wrist1",
    "wrist_2_link": "wrist2",
    "wrist_3_link": "wrist3",
}
_UR_MESH = re.compile(r"ur_description/meshes/([^/]+)/(visual|collision)/([^/]+)\.[A-Za-z]+$")


def is_arm_mesh(element: ET.Element, arm_link: str, ur_model: str) -> bool:
    """Whether ``element`` (a ``<visual>`` or ``<collision>`` of the arm link ``arm_link``,
    unprefixed, of a ``ur_model`` arm) is ur_description's own mesh of that link, model and
    kind, unscaled: the geometry the cell's arm has there. Another file of ur_description
    (the upper arm's mesh on the forearm, a UR10's on a UR5, a collision mesh as the
    visual) or a ``scale`` is the student's, loaded as written."""
    mesh = element.find("geometry/mesh")
    match = _UR_MESH.search(mesh.get("filename", "")) if mesh is not None else None
    if (
        mesh is None
        or match is None
        or match.groups() != (ur_model, element.tag, UR_LINK_MESHES.get(arm_link))
    ):
        return False
    try:
        scale = [float(v) for v in (mesh.get("scale") or "1 1 1").split()]
    except ValueError:
        return False
    return all(abs(v - 1.0) < 1e-9 for v in scale)


def _is_course_mesh(element: ET.Element) -> bool:
    mesh = element.find("geometry/mesh")
    return mesh is not None and any(m in mesh.get("filename", "") for m in _COURSE_MESHES)


def inner_additions_urdf(link: str, extras: list[ET.Element], name: str) -> str:
    """A URDF named ``name`` of one link ``<link>_own`` holding ``extras`` as written (the
    cell welds it to its own ``link``)."""
    out = ET.Element("robot", name=name)
    own = ET.SubElement(out, "link", name=f"{link}_own")
    own.extend(copy.deepcopy(e) for e in extras)
    return ET.tostring(out, encoding="unicode")
