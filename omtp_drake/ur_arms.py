"""The classic UR arms (UR5, UR10) of the course, from ``example-robot-data``'s ``ur_description``:
a Drake-ready URDF per arm, its links and joints prefixed as the course's ``robotN_`` arms, written
once into the model cache (:func:`~omtp_drake.assets.cache_entry`) with its meshes converted.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from pathlib import Path

from omtp_drake.assets import DRAKE_NS, UR_MODELS, cache_entry, drake_mesh, write_atomic
from omtp_drake.errors import ConfigError, UnknownNameError


@functools.cache
def ur_description_dir() -> Path:
    """The installed ``ur_description`` folder of ``example-robot-data``."""
    dist = importlib.metadata.distribution("example-robot-data")
    path = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots/ur_description")))
    if not (path / "urdf").is_dir():
        raise ConfigError(f"example-robot-data is installed but has no ur_description at {path}")
    return path


def ur_urdf(
    model: str,
    prefix: str,
    *,
    joint_limit: float | Sequence[float] = math.pi,
    velocity: Sequence[float] = (),
    effort: Sequence[float] = (),
    inertials: Mapping[str, Sequence[float]] | None = None,
    dropped: Sequence[str] = (),
) -> Path:
    """A Drake-ready URDF of a classic UR arm, with every link and joint prefixed.

    Args:
        model: ``"ur5"`` or ``"ur10"``.
        prefix: prepended to link, joint and actuator names (``"robot1_"``).
        joint_limit: symmetric position limit of every joint (the course: pi), or of each
            revolute joint in the file's order (pan, lift, elbow, wrist 1, 2, 3).
        velocity: each revolute joint's velocity limit (rad/s), in that order; empty:
            the file's.
        effort: each revolute joint's effort limit (N m), likewise (Drake's plant clamps
            the arm's actuation to them).
        inertials: link (unprefixed) -> [mass, x, y, z, ixx, iyy, izz, ixy, ixz, iyz], the
            link's inertial in its frame (centre of mass, inertia about it); a link not
            given: the file's.
        dropped: ``<link>/visual`` or ``<link>/collision`` (unprefixed): geometry of the
            file's removed (a student's file replaced it; theirs is loaded beside).

    The ``world`` link and its joint are dropped (the station welds
    ``<prefix>base_link`` where it belongs), ``ee_link``'s 1 cm collision box is
    removed, collision meshes are declared convex and mesh paths point into the
    cache. The robot is named ``prefix`` without its trailing underscore.
    """
    if model not in UR_MODELS:
        raise UnknownNameError("arm model", model, UR_MODELS)
    src = ur_description_dir() / "urdf" / f"{model}_robot.urdf"
    name = prefix.rstrip("_") or model
    edits = _edits_tag(velocity, effort, inertials or {}, dropped)
    dst = cache_entry(f"{name}_{model}_{_limit_tag(joint_limit)}{edits}{_FORM}.urdf")
    if dst.exists():
        return dst

    ET.register_namespace("drake", DRAKE_NS)
    root = ET.parse(src).getroot()
    root.set("name", name)
    _drop_world_and_ee_collision(root)
    _prefix_names(root, prefix, joint_limit)
    _set_rates(root, velocity, effort)
    _set_inertials(root, prefix, inertials or {})
    _drop_geometry(root, prefix, dropped)
    _point_meshes_to(root)
    write_atomic(dst, ET.tostring(root, encoding="utf-8", xml_declaration=True))
    return dst


@functools.cache
def model_rates(model: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """(velocity limits, effort limits) of ``model``'s revolute joints in its file's order
    (pan, lift, elbow, wrist 1, 2, 3), as ur_description writes them."""
    if model not in UR_MODELS:
        raise UnknownNameError("arm model", model, UR_MODELS)
    limits = _revolute_limits(ET.parse(ur_description_dir() / "urdf" / f"{model}_robot.urdf").getroot())
    return (
        tuple(float(limit.get("velocity", "inf")) for limit in limits),
        tuple(float(limit.get("effort", "inf")) for limit in limits),
    )


def _revolute_limits(root: ET.Element) -> list[ET.Element]:
    """The ``<limit>`` of each revolute joint of a UR file that has one, in the file's order."""
    joints = [j for j in root.findall("joint") if j.get("type") == "revolute"]
    return [limit for j in joints if (limit := j.find("limit")) is not None]


def _drop_world_and_ee_collision(root: ET.Element) -> None:
    """Removes ``<gazebo>``, the ``world`` link and its joint, and ``ee_link``'s collision box."""
    for el in root.findall("gazebo"):
        root.remove(el)
    for joint in root.findall("joint"):
        if _attr(_child(joint, "parent"), "link") == "world":
            root.remove(joint)
    for link in root.findall("link"):
        if link.get("name") == "world":
            root.remove(link)
        if link.get("name") == "ee_link":
            for col in link.findall("collision"):
                link.remove(col)


def _prefix_names(root: ET.Element, prefix: str, joint_limit: float | Sequence[float]) -> None:
    """Prefixes link, joint, transmission and actuator names; sets revolute limits to +/- ``joint_limit``
    (one for all, or one each in the file's order)."""
    revolute = [
        j for j in root.findall("joint") if j.get("type") == "revolute" and j.find("limit") is not None
    ]
    if isinstance(joint_limit, (int, float)):
        each = [float(joint_limit)] * len(revolute)
    else:
        each = [float(v) for v in joint_limit]
    if len(each) != len(revolute):
        raise ConfigError(f"UR model: {len(each)} joint limits for {len(revolute)} revolute joints")
    limits = {id(j): v for j, v in zip(revolute, each)}
    for link in root.findall("link"):
        link.set("name", prefix + _attr(link, "name"))
    for joint in root.findall("joint"):
        joint.set("name", prefix + _attr(joint, "name"))
        for tag in ("parent", "child"):
            el = _child(joint, tag)
            el.set("link", prefix + _attr(el, "link"))
        limit = joint.find("limit")
        if limit is not None and id(joint) in limits:
            limit.set("lower", repr(-limits[id(joint)]))
            limit.set("upper", repr(limits[id(joint)]))
    for trans in root.findall("transmission"):
        trans.set("name", prefix + _attr(trans, "name"))
        trans_joint = _child(trans, "joint")
        trans_joint.set("name", prefix + _attr(trans_joint, "name"))
        actuator = _child(trans, "actuator")
        actuator.set("name", prefix + _attr(actuator, "name"))


def _set_rates(root: ET.Element, velocity: Sequence[float], effort: Sequence[float]) -> None:
    """Sets the revolute joints' velocity and effort limits (in the file's order) where given."""
    limits = _revolute_limits(root)
    for attribute, values in (("velocity", velocity), ("effort", effort)):
        if not values:
            continue
        if len(values) != len(limits):
            raise ConfigError(f"UR model: {len(values)} {attribute} limits for {len(limits)} revolute joints")
        for limit, value in zip(limits, values):
            limit.set(attribute, repr(float(value)))


def _set_inertials(root: ET.Element, prefix: str, inertials: Mapping[str, Sequence[float]]) -> None:
    """Writes each given link's inertial (see :func:`ur_urdf`) in place of the file's."""
    for link_name, values in inertials.items():
        link = root.find(f"link[@name='{prefix}{link_name}']")
        if link is None:
            raise UnknownNameError("UR link", link_name, [_attr(k, "name") for k in root.findall("link")])
        for old in link.findall("inertial"):
            link.remove(old)
        m, x, y, z, ixx, iyy, izz, ixy, ixz, iyz = (float(v) for v in values)
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "mass", value=repr(m))
        ET.SubElement(inertial, "origin", xyz=f"{x!r} {y!r} {z!r}", rpy="0 0 0")
        moments = {"ixx": ixx, "iyy": iyy, "izz": izz, "ixy": ixy, "ixz": ixz, "iyz": iyz}
        ET.SubElement(inertial, "inertia", {k: repr(v) for k, v in moments.items()})


def _drop_geometry(root: ET.Element, prefix: str, dropped: Sequence[str]) -> None:
    """Removes the file's visuals or collisions of each ``<link>/<kind>`` of ``dropped``."""
    for entry in dropped:
        link_name, _, kind = entry.partition("/")
        link = root.find(f"link[@name='{prefix}{link_name}']")
        if link is None or kind not in ("visual", "collision"):
            raise UnknownNameError("UR link geometry", entry, [])
        for element in link.findall(kind):
            link.remove(element)


def _point_meshes_to(root: ET.Element) -> None:
    """Points every mesh at its converted file (:func:`drake_mesh`); collision meshes are declared
    convex, each pointing at its convex hull (:func:`convex_hull_file`)."""
    package = "package://example-robot-data/robots/ur_description/"
    for kind in ("visual", "collision"):
        for mesh in root.iterfind(f"link/{kind}/geometry/mesh"):
            filename = _attr(mesh, "filename")
            if not filename.startswith(package):
                raise ConfigError(f"UR model: mesh {filename!r} is not in {package}")
            src = ur_description_dir() / filename[len(package) :]
            converted = drake_mesh(src, collision=kind == "collision")
            mesh.set("filename", str(converted if kind == "visual" else convex_hull_file(converted)))
            if kind == "collision":
                ET.SubElement(mesh, f"{{{DRAKE_NS}}}declare_convex")


#: How far (m) a UR link's collision hull may lie inside Drake's exact hull of its mesh
#: (:func:`convex_hull_file`): the hull keeps the fewest vertices that stay this close.
HULL_TOLERANCE = 0.002
#: In a cached URDF's name: its collision meshes are their hulls' files (of this tolerance).
_FORM = f"_hulls{HULL_TOLERANCE * 1000:g}mm"


def convex_hull_file(obj: Path) -> Path:
    """A convex hull of the mesh ``obj`` as an ``.obj`` of its vertices and faces, written once
    into the model cache by the mesh's name (itself the source's content hash): Drake's own
    hull (the one its point contact uses for a mesh declared convex), with only the vertices
    it needs to stay within :data:`HULL_TOLERANCE` of it (:func:`_fewer_vertices`).

    A mesh declared convex is its hull to Drake, and each geometry registered with a
    SceneGraph reads, checksums and hulls its file, then builds its collision shape: for a UR
    link's 120-245 hull vertices that is 10-16 ms, superlinear in the vertices, 7 links an
    arm, an arm in every cell and in every planner's copy of the cell. The UR's collision
    meshes are themselves coarse stand-ins for the links (ur_description's), and the 2 mm
    hull has 43-85 vertices: a UR10's seven collision hulls into a SceneGraph 72 -> 22 ms."""
    dst = cache_entry(f"meshes/{obj.stem}-hull-{HULL_TOLERANCE * 1000:g}mm.obj")
    if dst.exists():
        return dst
    import numpy as np
    import trimesh
    from pydrake.geometry import Mesh

    hull = Mesh(str(obj)).GetConvexHull()
    p_MV = np.array([hull.vertex(i) for i in range(hull.num_vertices())], dtype=float)
    kept = trimesh.convex.convex_hull(
        p_MV[_fewer_vertices(p_MV, HULL_TOLERANCE)]
    )  # as convex_pieces writes one
    write_atomic(dst, kept.export(file_type="obj", digits=17).encode())
    return dst


def _fewer_vertices(p_MV, tolerance: float) -> list[int]:
    """Indices of a subset of the points ``p_MV`` (N x 3, the vertices of a convex hull) whose
    hull every point lies within ``tolerance`` of: the six extreme points along the axes, then,
    one at a time, the point farthest outside the subset's hull (deterministic)."""
    import numpy as np
    from scipy.spatial import ConvexHull

    chosen = list(dict.fromkeys(int(i) for i in (*p_MV.argmin(axis=0), *p_MV.argmax(axis=0))))
    while len(chosen) < 4 or not _spans_a_volume(p_MV[chosen]):
        distance = np.min(np.linalg.norm(p_MV[:, None, :] - p_MV[chosen][None, :, :], axis=2), axis=1)
        chosen.append(int(np.argmax(distance)))
    while True:
        planes = ConvexHull(p_MV[chosen]).equations  # n.x + d <= 0 inside, n unit
        outside = (p_MV @ planes[:, :3].T + planes[:, 3]).max(axis=1)
        farthest = int(np.argmax(outside))
        if outside[farthest] <= tolerance:
            return chosen
        chosen.append(farthest)


def _spans_a_volume(points) -> bool:
    import numpy as np

    return bool(np.linalg.matrix_rank(points[1:] - points[0], tol=1e-9) == 3)


def _child(element: ET.Element, tag: str) -> ET.Element:
    found = element.find(tag)
    if found is None:
        raise ConfigError(f"UR model: <{element.tag} name={element.get('name')!r}> has no <{tag}>")
    return found


def _attr(element: ET.Element, name: str) -> str:
    value = element.get(name)
    if value is None:
        raise ConfigError(f"UR model: <{element.tag}> has no attribute {name!r}")
    return value


def _edits_tag(
    velocity: Sequence[float], effort: Sequence[float], inertials: Mapping, dropped: Sequence[str]
) -> str:
    """The cache name's part for what a scenario changes of the file ('' for nothing)."""
    rates = "".join(
        f"_{tag}" + "_".join(f"{v:.6g}" for v in values)
        for tag, values in (("v", velocity), ("e", effort))
        if values
    )
    if inertials:
        text = repr(sorted((k, [float(v) for v in vs]) for k, vs in inertials.items()))
        rates += "_i" + hashlib.sha1(text.encode()).hexdigest()[:12]
    if dropped:
        rates += "_d" + hashlib.sha1(" ".join(sorted(dropped)).encode()).hexdigest()[:12]
    return rates


def _limit_tag(limit: float | Sequence[float]) -> str:
    if isinstance(limit, (int, float)):
        return f"lim{round(limit * 1e4)}"
    values = [float(v) for v in limit]
    if len(set(values)) == 1:
        return f"lim{round(values[0] * 1e4)}"  # (the same file as one limit for all)
    return "lim" + "_".join(str(round(v * 1e4)) for v in values)
