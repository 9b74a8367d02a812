"""A URDF's links as frames: the tree of its joints, each link's pose for given joint
values, and its ``<gazebo>`` extension tags (materials, sensors, plugins by link).

Every URDF link stays a tf frame: :meth:`UrdfModel.link_poses` gives ``X_ML`` of each
link in the model frame (the root link's), as robot_state_publisher computes it from
the joints' origins (``xyz``, ``rpy``), axes and positions.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from pydrake.common.eigen_geometry import AngleAxis
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from omtp_drake.errors import WorkspaceError


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    X_PJ: RigidTransform
    axis: np.ndarray


@dataclass
class UrdfModel:
    """A URDF's name, links, joints and ``<gazebo>`` tags (by ``reference``, '' for the model)."""

    name: str
    source: str
    links: list[str]
    joints: dict[str, UrdfJoint]
    gazebo: list[tuple[str, ET.Element]] = field(default_factory=list)
    root_element: ET.Element | None = None

    @classmethod
    def from_text(cls, text: str, source: str) -> UrdfModel:
        """The URDF ``text`` (``source`` names it in errors: the param and the file it came from)."""
        try:
            root = ET.fromstring(text)
        except ET.ParseError as e:
            raise WorkspaceError(f"{source}: not well-formed URDF: {e}") from None
        if root.tag != "robot":
            raise WorkspaceError(f"{source}: not a URDF (its root is <{root.tag}>, not <robot>)")
        links = [link.get("name", "") for link in root.findall("link")]
        joints = {}
        for element in root.findall("joint"):
            joint = _joint(element, source)
            joints[joint.name] = joint
        gazebo = [(g.get("reference", ""), g) for g in root.findall("gazebo")]
        model = cls(root.get("name", ""), source, links, joints, gazebo, root)
        model._check_tree()
        return model

    def _check_tree(self) -> None:
        known = set(self.links)
        parents: dict[str, str] = {}
        for joint in self.joints.values():
            for link in (joint.parent, joint.child):
                if link not in known:
                    raise WorkspaceError(
                        f"{self.source}: joint {joint.name!r} names link {link!r}, which is not defined"
                    )
            if joint.child in parents:
                raise WorkspaceError(
                    f"{self.source}: link {joint.child!r} has two parent joints "
                    f"({parents[joint.child]}, {joint.name})"
                )
            parents[joint.child] = joint.name
        roots = [link for link in self.links if link not in parents]
        if len(roots) != 1:
            raise WorkspaceError(f"{self.source}: a URDF needs one root link, found {roots or 'none'}")

    @property
    def root(self) -> str:
        children = {j.child for j in self.joints.values()}
        return next(link for link in self.links if link not in children)

    def link_poses(self, positions: Mapping[str, float] | None = None) -> dict[str, RigidTransform]:
        """``X_RL`` of every link in the root link's frame, at ``positions`` (joint name ->
        value; 0 for the others)."""
        positions = positions or {}
        by_parent: dict[str, list[UrdfJoint]] = {}
        for joint in self.joints.values():
            by_parent.setdefault(joint.parent, []).append(joint)
        poses = {self.root: RigidTransform()}
        stack = [self.root]
        while stack:
            parent = stack.pop()
            for joint in by_parent.get(parent, []):
                poses[joint.child] = (
                    poses[parent] @ joint.X_PJ @ _motion(joint, positions.get(joint.name, 0.0))
                )
                stack.append(joint.child)
        return poses

    def static_links(self) -> list[str]:
        """The links fixed to the root link (through fixed joints only), root included."""
        fixed: dict[str, list[str]] = {}
        for joint in self.joints.values():
            if joint.type == "fixed":
                fixed.setdefault(joint.parent, []).append(joint.child)
        out, stack = [], [self.root]
        while stack:
            link = stack.pop()
            out.append(link)
            stack += fixed.get(link, [])
        return out

    def joint_names(self, kind: str | None = None) -> list[str]:
        return [j.name for j in self.joints.values() if kind is None or j.type == kind]


def _motion(joint: UrdfJoint, q: float) -> RigidTransform:
    if joint.type in ("revolute", "continuous"):
        return RigidTransform(RotationMatrix(AngleAxis(q, joint.axis)), [0.0, 0.0, 0.0])
    if joint.type == "prismatic":
        return RigidTransform(joint.axis * q)
    return RigidTransform()


def _joint(element: ET.Element, source: str) -> UrdfJoint:
    name = element.get("name", "")
    kind = element.get("type", "")
    parent, child = element.find("parent"), element.find("child")
    if parent is None or child is None:
        raise WorkspaceError(f"{source}: joint {name!r} needs a parent and a child")
    origin = element.find("origin")
    X_PJ = RigidTransform()
    if origin is not None:
        xyz = _numbers(origin.get("xyz", "0 0 0"), 3, source, f"joint {name!r} origin xyz")
        rpy = _numbers(origin.get("rpy", "0 0 0"), 3, source, f"joint {name!r} origin rpy")
        X_PJ = RigidTransform(RollPitchYaw(rpy), xyz)
    axis_element = element.find("axis")
    axis = np.array([1.0, 0.0, 0.0])
    if axis_element is not None:
        axis = np.array(_numbers(axis_element.get("xyz", "1 0 0"), 3, source, f"joint {name!r} axis"))
        norm = np.linalg.norm(axis)
        if norm == 0:
            raise WorkspaceError(f"{source}: joint {name!r} has a zero axis")
        axis = axis / norm
    return UrdfJoint(name, kind, parent.get("link", ""), child.get("link", ""), X_PJ, axis)


def _numbers(text: str, n: int, source: str, what: str) -> list[float]:
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) != n or not all(np.isfinite(values)):
        raise WorkspaceError(f"{source}: {what} needs {n} numbers, got {text!r}")
    return values
