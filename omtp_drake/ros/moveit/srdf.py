"""MoveIt's semantic robot description (SRDF) on the cell's arms.

A MoveIt config's ``config/<robot>.srdf`` names the move groups, their named
states (``group_state``), end effectors and the link pairs whose collisions are
never checked (``disable_collisions``). :func:`parse_srdf` reads one against the
cell's kinematic tree (:class:`CellTree`) into a :class:`SemanticModel`;
:func:`default_semantic` is the cell's own (the course's named poses), used when a
run is given no SRDF.

Groups are defined, as in srdfdom, by ``chain`` (``base_link`` .. ``tip_link``),
``joint``, ``link`` or ``group`` (a subgroup) elements; a ``joint`` naming one of the
SRDF's virtual joints is no joint of the cell and is left out. A group that moves joints
must move the six joints of one arm: it is a move group on that arm (its name is
the student's, ``robot1`` in the course). A group without joints (a gripper's
links) is an end-effector group. A joint, link or group the cell lacks is a
ConfigError naming it and the valid ones; a group moving part of an arm, or
joints of two arms, is a NotSupportedError. As srdfdom does, a disabled
collision pair naming a link the cell lacks is skipped with a warning (the
course's SRDF names links of the Gazebo world the cell has no body for).
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Optional

from omtp_drake.errors import ConfigError, NotSupportedError, UnknownNameError

_log = logging.getLogger("moveit_commander")


@dataclass(frozen=True)
class CellTree:
    """The cell's kinematic tree as an SRDF sees it (names as in the URDF).

    Attributes:
        parent: child link -> (joint, parent link, whether the joint moves).
        arms: robot -> its six joints (pan ... wrist 3), by their full names.
        tool_links: robot -> its tool links (gripper links and ``tool0``) by name.
    """

    parent: Mapping[str, tuple[str, str, bool]]
    arms: Mapping[str, tuple[str, ...]]
    tool_links: Mapping[str, tuple[str, ...]] = field(default_factory=dict)

    @property
    def links(self) -> set[str]:
        return set(self.parent) | {p for _j, p, _m in self.parent.values()}

    @property
    def joints(self) -> dict[str, str]:
        """joint -> its child link."""
        return {j: child for child, (j, _p, _m) in self.parent.items()}

    def robot_of_joint(self, joint: str) -> Optional[str]:
        return next((r for r, joints in self.arms.items() if joint in joints), None)

    def chain_joints(self, base: str, tip: str, group: str) -> list[str]:
        """The moving joints from link ``base`` down to link ``tip``."""
        link, moving = tip, []
        while link != base:
            if link not in self.parent:
                raise ConfigError(
                    f"SRDF group {group!r}: {tip!r} is not below {base!r} in the cell's tree "
                    "(a chain goes from a base link down to a tip link)"
                )
            joint, link, moves = self.parent[link]
            if moves:
                moving.append(joint)
        return moving[::-1]

    def link_joint(self, link: str) -> list[str]:
        """The moving joint whose child ``link`` is (a link's group member), if any."""
        joint, _parent, moves = self.parent.get(link, ("", "", False))
        return [joint] if moves else []


@dataclass(frozen=True)
class Group:
    """A group of the SRDF: the arm it moves (None: an end-effector group), its
    moving joints, its links and, for a chain, the chain's tip link."""

    name: str
    robot: Optional[str]
    joints: tuple[str, ...]
    links: tuple[str, ...] = ()
    tip_link: Optional[str] = None


@dataclass(frozen=True)
class EndEffector:
    """An SRDF ``end_effector``: its group, the link it hangs from, the arm's group."""

    name: str
    group: str
    parent_link: str
    parent_group: Optional[str] = None


@dataclass(frozen=True)
class SemanticModel:
    """A robot's semantics (see the module doc): ``text`` is the SRDF's own text."""

    name: str
    text: str
    groups: Mapping[str, Group]
    states: Mapping[str, Mapping[str, Mapping[str, float]]]
    end_effectors: tuple[EndEffector, ...] = ()
    disabled_collisions: tuple[tuple[str, str, str], ...] = ()

    def group(self, name: str) -> Group:
        """The group ``name``; UnknownNameError listing the groups."""
        if name not in self.groups:
            raise UnknownNameError("move group", name, self.groups)
        return self.groups[name]

    def move_groups(self) -> list[str]:
        """The groups that move an arm, in the SRDF's order."""
        return [g for g, group in self.groups.items() if group.robot is not None]

    def group_of(self, robot: str) -> Optional[str]:
        """The first move group on arm ``robot`` (None: none moves it)."""
        return next((g for g in self.move_groups() if self.groups[g].robot == robot), None)

    def named_states(self, group: str) -> dict[str, dict[str, float]]:
        """The named states of ``group``: name -> {joint: value}, in the SRDF's order."""
        self.group(group)
        return {k: dict(v) for k, v in self.states.get(group, {}).items()}

    def end_effector_link(self, group: str) -> Optional[str]:
        """MoveIt's end-effector link of ``group``: the parent link of the end effector
        whose parent group it is, else the tip of its chain (None: neither)."""
        own = self.group(group)
        for eef in self.end_effectors:
            if eef.parent_group == group or (eef.parent_group is None and eef.parent_link in own.links):
                return eef.parent_link
        return own.tip_link


# ----------------------------------------------------------------------------- parsing


def parse_srdf(text: str, tree: CellTree, source: str = "SRDF") -> SemanticModel:
    """The :class:`SemanticModel` of the SRDF ``text`` on the cell ``tree``.

    Raises:
        ConfigError: not an SRDF, or a group, joint or link the cell lacks (named,
            with the valid ones), or a bad joint value.
        NotSupportedError: a group moving part of an arm or joints of two arms.
    """
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise ConfigError(f"{source} is not valid XML: {e}") from None
    if root.tag != "robot":
        raise ConfigError(f"{source}: the root element is <{root.tag}>, an SRDF's is <robot>")
    # A group may list the virtual joint (the robot's root in the world): no joint of the cell.
    virtual = {v.get("name") for v in root.findall("virtual_joint")}
    elements = {
        g.get("name", ""): [c for c in g if not (c.tag == "joint" and c.get("name") in virtual)]
        for g in root.findall("group")
    }
    groups: dict[str, Group] = {}
    for name in elements:
        _resolve_group(name, elements, tree, groups, ())
    states = _states(root, groups, tree)
    end_effectors = tuple(_end_effector(e, groups, tree) for e in root.findall("end_effector"))
    return SemanticModel(
        name=root.get("name", ""),
        text=text,
        groups=groups,
        states=states,
        end_effectors=end_effectors,
        disabled_collisions=_disabled_pairs(root, tree),
    )


def bad_name(kind: str, name: str, valid: Any, *, closest: bool = False) -> ConfigError:
    """A ConfigError for a name in a config file that is not one of ``valid`` (the
    message of :class:`UnknownNameError`: the closest names, the valid ones)."""
    return ConfigError(str(UnknownNameError(kind, name, valid, closest=closest)))


def _resolve_group(
    name: str, elements: Mapping[str, list[ET.Element]], tree: CellTree, done: dict[str, Group], seen: tuple
) -> Group:
    if name in done:
        return done[name]
    if not name:
        raise ConfigError("SRDF: a <group> has no name")
    if name in seen:
        raise ConfigError(f"SRDF group {name!r} contains itself (through {' -> '.join(seen)})")
    joints: list[str] = []
    links: list[str] = []
    tip = None
    for child in elements[name]:
        what = child.get("name", "")
        if child.tag == "chain":
            base = _link(child.get("base_link", ""), name, tree)
            tip = _link(child.get("tip_link", ""), name, tree)
            joints += tree.chain_joints(base, tip, name)
            links.append(tip)
        elif child.tag == "joint":
            joints += _group_joint(what, name, tree)
        elif child.tag == "link":
            links.append(_link(what, name, tree))
            joints += tree.link_joint(what)
        elif child.tag == "group":
            if what not in elements:
                raise bad_name(f"subgroup of SRDF group {name!r}", what, elements)
            sub = _resolve_group(what, elements, tree, done, (*seen, name))
            joints += sub.joints
            links += sub.links
            tip = tip or sub.tip_link
    done[name] = Group(name, _robot(name, joints, tree), tuple(dict.fromkeys(joints)), tuple(links), tip)
    return done[name]


def _link(link: str, group: str, tree: CellTree) -> str:
    if link not in tree.links:
        raise bad_name(f"link (SRDF group {group!r})", link, tree.links, closest=True)
    return link


def _group_joint(joint: str, group: str, tree: CellTree) -> list[str]:
    joints = tree.joints
    if joint not in joints:
        arm_joints = [j for arm in tree.arms.values() for j in arm]
        raise bad_name(f"joint (SRDF group {group!r})", joint, arm_joints, closest=True)
    return tree.link_joint(joints[joint])


def _robot(group: str, joints: list[str], tree: CellTree) -> Optional[str]:
    """The arm whose six joints ``joints`` are (None: no joints)."""
    if not joints:
        return None
    robots = {tree.robot_of_joint(j) for j in joints}
    for robot, arm_joints in tree.arms.items():
        if robots == {robot} and set(joints) == set(arm_joints):
            return robot
    raise NotSupportedError(
        f"SRDF group {group!r} moves {', '.join(joints)}: a move group of omtp-drake ros-run moves "
        f"the six joints of one arm ({'; '.join(f'{r}: {j[0]} ... {j[-1]}' for r, j in tree.arms.items())})"
    )


def _states(root: ET.Element, groups: Mapping[str, Group], tree: CellTree) -> dict[str, dict]:
    states: dict[str, dict[str, dict[str, float]]] = {}
    for element in root.findall("group_state"):
        name, group = element.get("name", ""), element.get("group", "")
        if group not in groups:
            raise bad_name(f"group (SRDF group_state {name!r})", group, groups)
        valid = groups[group].joints
        values: dict[str, float] = {}
        for joint in element.findall("joint"):
            jname = joint.get("name", "")
            if jname not in valid:
                raise bad_name(f"joint of group {group!r} (SRDF group_state {name!r})", jname, valid)
            values[jname] = _number(joint.get("value"), f"SRDF group_state {name!r}, joint {jname!r}")
        states.setdefault(group, {})[name] = values
    return states


def _number(value: Any, what: str) -> float:
    try:
        return float(str(value).split()[0])
    except (ValueError, IndexError):
        raise ConfigError(f"{what}: value {value!r} is not a number") from None


def _end_effector(element: ET.Element, groups: Mapping[str, Group], tree: CellTree) -> EndEffector:
    name = element.get("name", "")
    group, parent_group = element.get("group", ""), element.get("parent_group")
    for g in (group, parent_group):
        if g is not None and g not in groups:
            raise bad_name(f"group (SRDF end_effector {name!r})", g, groups)
    link = element.get("parent_link", "")
    if link not in tree.links:
        raise bad_name(f"parent_link (SRDF end_effector {name!r})", link, tree.links, closest=True)
    return EndEffector(name, group, link, parent_group)


def _disabled_pairs(root: ET.Element, tree: CellTree) -> tuple[tuple[str, str, str], ...]:
    links = tree.links
    pairs, unknown = [], set()
    for element in root.findall("disable_collisions"):
        a, b = element.get("link1", ""), element.get("link2", "")
        missing = [x for x in (a, b) if x not in links]
        if missing:
            unknown.update(missing)
            continue
        pairs.append((a, b, element.get("reason", "")))
    if unknown:
        _log.warning(
            "SRDF: disable_collisions skipped for links the cell does not have: %s",
            ", ".join(sorted(unknown)),
        )
    return tuple(pairs)


# ----------------------------------------------------------------------------- the cell's own


def default_semantic(tree: CellTree, poses: Mapping[str, Mapping[str, tuple[float, ...]]]) -> SemanticModel:
    """The cell's own semantics: a group per arm (named as the arm, a chain from its
    base link to its end-effector link) with ``poses`` (robot -> name -> six values)
    as its named states; ``text`` is that SRDF."""
    groups, states = {}, {}
    for robot, joints in tree.arms.items():
        tip = tree.tool_links.get(robot, ("",))[0]
        groups[robot] = Group(robot, robot, joints, (tip,), tip)
        if poses.get(robot):
            states[robot] = {n: dict(zip(joints, map(float, q))) for n, q in poses[robot].items()}
    model = SemanticModel("omtp", "", groups, states)
    return SemanticModel("omtp", to_srdf(model, tree), groups, states)


def to_srdf(model: SemanticModel, tree: CellTree) -> str:
    """``model`` as SRDF text (groups as chains from the arm's base link)."""
    root = ET.Element("robot", name=model.name)
    for group in model.groups.values():
        element = ET.SubElement(root, "group", name=group.name)
        if group.robot is not None and group.tip_link:
            base = tree.parent[tree.joints[group.joints[0]]][1]
            ET.SubElement(element, "chain", base_link=base, tip_link=group.tip_link)
        else:
            for link in group.links:
                ET.SubElement(element, "link", name=link)
    for group_name, states in model.states.items():
        for name, values in states.items():
            element = ET.SubElement(root, "group_state", name=name, group=group_name)
            for joint, value in values.items():
                ET.SubElement(element, "joint", name=joint, value=repr(value))
    for a, b, reason in model.disabled_collisions:
        ET.SubElement(root, "disable_collisions", link1=a, link2=b, reason=reason)
    ET.indent(root, "    ")
    return '<?xml version="1.0" ?>\n' + ET.tostring(root, encoding="unicode") + "\n"
