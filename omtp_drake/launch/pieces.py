"""The course's pieces recognised in a spawned URDF, as the scenario's entries.

A model ``spawn_model`` puts in the world is read for the pieces of the course's cell,
by the link names the course's macros give (``omtp_support``'s ``robot_system``,
``robot_pedestal``, ``bin``, ``break_beam``, ``workcell``; ``ur_description``'s arms):

- an arm: joints ``<prefix>shoulder_pan_joint`` ... (a UR10 or a UR5 by its upper arm's
  length), its base where the model puts ``<prefix>base_link``; a gripper: links
  ``<g>base_link`` and ``<g>suction_cup`` on its ``tool0`` with a ROSVacuumGripperPlugin;
- a pedestal: ``<prefix>pedestal_link`` (a box; its height);
- a bin: ``<prefix>base_link`` with ``<prefix>drop_point``;
- the break beam: ``<prefix>optical_link`` with a ray sensor and a ROSProximityRayPlugin
  (where the course has it, or where the student moved it: it senses there);
- the workcell (the conveyor's frame and the floor's meshes): a link ``workcell``.

Every other model is loaded as it is (a typed model entry of the scenario: its own
geometry, joints, inertia; see :mod:`omtp_drake.launch.nodes`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.assets import model_dimensions
from omtp_drake.cell.cell_models import X_W_BREAK_BEAM
from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.arm_dynamics import ARM_JOINTS, arm_inertials, arm_joint_rates
from omtp_drake.launch.mesh_bins import has_mesh_collision, mesh_bin_walls
from omtp_drake.launch.own_links import (
    WORKCELL_LINK,
    Claims,
    bin_walls,
    inner_additions,
    inner_additions_urdf,
    mount_urdf,
    mounts,
    own_links,
    own_links_urdf,
    piece_urdf,
    replaced_kinds,
)
from omtp_drake.launch.plugins import beam_names, check_break_beam, gripper_names, plugins_in, suction_checks
from omtp_drake.launch.urdf_model import UrdfModel
from omtp_drake.scenario import RobotConfig
from omtp_drake.scenario.arm_dynamics import ARM_LINKS

#: Length of the upper arm (the elbow joint's offset along the link) -> the arm model.
UR_UPPER_ARMS = {"ur10": 0.612, "ur5": 0.425}
_TOL = 1e-3
#: The plugins a spawned URDF's pieces carry (read where their pieces are read).
URDF_PLUGINS = ("suction", "break_beam", "controllers")
#: The links the course's macros give each piece, after its prefix (ur_description's arms,
#: Melodic's and later; omtp_support's gripper, pedestal, break beam): the pieces' own.
PIECE_LINKS = {
    "arm": (
        "base_link", "base", "base_link_inertia", "shoulder_link", "upper_arm_link", "forearm_link",
        "wrist_1_link", "wrist_2_link", "wrist_3_link", "ee_link", "flange", "tool0",
    ),
    "gripper": ("base_link", "suction_cup"),
    "pedestal": ("pedestal_link",),
    "break_beam": ("world_interface", "base_link", "optical_link"),
}  # fmt: skip
#: An arm's six joints, after its prefix (ur_description's).
PIECE_JOINTS = ARM_JOINTS


@dataclass
class Pieces:
    """What the spawned models add to the scenario, and the lines to warn with."""

    robots: list[dict] = field(default_factory=list)
    pedestals: dict[str, tuple[np.ndarray, float, str]] = field(default_factory=dict)
    bins: list[dict] = field(default_factory=list)
    break_beam: bool = False
    #: Where the student moved the break beam's base (empty: the course's pose).
    break_beam_pose: list[float] = field(default_factory=list)
    suction_checks: int | None = None
    #: The course's plugins' ROS names read from their ``<plugin>``s (the scenario's
    #: ``plugin_names``: ``grippers`` and the beam's).
    plugin_names: dict = field(default_factory=lambda: {"grippers": []})
    warnings: list[str] = field(default_factory=list)
    #: The spawned URDF models and where they were placed (their links are tf frames).
    models: list[tuple[UrdfModel, RigidTransform]] = field(default_factory=list)
    #: The links fixed to the world (their first placement), as the scenario's extra frames.
    frames: dict[str, RigidTransform] = field(default_factory=dict)
    #: What the student added beside the pieces (:mod:`~omtp_drake.launch.own_links`): the
    #: model's name, a URDF of those links as written, and where it came from.
    own: list[OwnModel] = field(default_factory=list)
    #: package or Gazebo model name -> folder (a mesh bin's meshes are read to measure it).
    packages: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class OwnModel:
    """Links of a spawned URDF the cell loads as written: a model of the scenario."""

    name: str
    text: str  # the URDF
    where: str
    pose: list[float]  # x y z R P Y in the world (in ``parent``, when it has one)
    static: bool = True
    #: Links whose collision meshes load as convex pieces (a mesh bin: ModelConfig.open_links).
    open_links: tuple[str, ...] = ()
    #: The link of a course piece it is welded to (it moves with it); '' for the world.
    parent: str = ""


def add_urdf_model(
    pieces: Pieces, model: UrdfModel, X_WM: RigidTransform, where: str, joints: dict, name: str = ""
) -> bool:
    """Adds the pieces of ``model`` (spawned as ``name``) placed at ``X_WM`` (``joints``:
    spawn_model's ``-J``), and the links the student added beside them, as written;
    False when it is none of the course's pieces (the caller loads it as it is)."""
    X_M = model.link_poses()
    claims = _piece_prefixes(pieces, model, X_WM, X_M, where, joints, name)
    if claims is None:
        return False  # loaded as it is: its own plugins are its model's (scenario.gazebo_tags)
    for reference, element in model.gazebo:
        for plugin in plugins_in(element, where, reference):
            if plugin.kind not in URDF_PLUGINS and not _loaded_with(model, reference, claims):
                pieces.warnings.append(plugin.unknown_line())
    pieces.models.append((model, X_WM))
    links, lines = own_links(model, claims, where)
    pieces.warnings += lines
    if links:
        # Named as the spawned model (a piece's own name taken: ``<name>_links``).
        own = name or model.name
        pieces_names = {p["name"] for p in (*pieces.robots, *pieces.bins)} | {o.name for o in pieces.own}
        own = f"{own}_links" if own in pieces_names else own
        pieces.own.append(OwnModel(own, own_links_urdf(model, links, X_WM, joints, own), where, [0.0] * 6))
    for mount in mounts(model, claims):  # on an arm or gripper: welded to the cell's link
        taken = {p["name"] for p in (*pieces.robots, *pieces.bins)} | {o.name for o in pieces.own}
        own = mount.root if mount.root not in taken else f"{mount.root}_model"
        pose = [*mount.X_PR.translation(), *RollPitchYaw(mount.X_PR.rotation()).vector()]
        text = mount_urdf(model, mount, own)
        pieces.own.append(OwnModel(own, text, where, [float(v) for v in pose], parent=mount.parent))
    _add_inner_additions(pieces, model, claims, where)
    for link in model.static_links():
        if link != "world" and link not in links:  # (world: Gazebo's name for the world itself)
            pieces.frames.setdefault(link, X_WM @ X_M[link])
    return True


def _add_inner_additions(pieces: Pieces, model: UrdfModel, claims: Claims, where: str) -> None:
    """What the student added inside a link of a course arm, gripper or the beam, or of the
    workcell's hall (which the cell builds, or stands its floor, belt and wall in for;
    :func:`~omtp_drake.launch.own_links.inner_additions`): one model entry ``<link>_own``
    each, welded to the cell's link of that name (pedestals and bins are loaded as written
    already)."""
    built = [link for link in sorted(claims.names) if not link.endswith("pedestal_link")]
    built += [WORKCELL_LINK] if WORKCELL_LINK in model.links else []
    bodies = {f"{r['name']}_{link}": r for r in pieces.robots for link in ARM_LINKS}
    meshed = {
        link: (link[len(bodies[link]["name"]) + 1 :], bodies[link]["model"])
        for link in sorted(set(built) & set(bodies))
    }
    for link, (unprefixed, ur_model) in meshed.items():
        robot = bodies[link]
        replaced = [f"{unprefixed}/{kind}" for kind in replaced_kinds(model, link, unprefixed, ur_model)]
        if replaced:
            robot["own_geometry"] = [*robot.get("own_geometry", []), *replaced]
    for link, extras in inner_additions(model, built, meshed).items():
        taken = {p["name"] for p in (*pieces.robots, *pieces.bins)} | {o.name for o in pieces.own}
        own = f"{link}_own" if f"{link}_own" not in taken else f"{link}_own_model"
        text = inner_additions_urdf(link, extras, own)
        pieces.own.append(OwnModel(own, text, where, [0.0] * 6, parent=link))


def _loaded_with(model: UrdfModel, link: str, claims: Claims) -> bool:
    """Whether the student's ``link`` is loaded as written (its sensors with it)."""
    own, _ = own_links(model, claims, "")
    return link in own or any(link in m.links for m in mounts(model, claims))


def _piece_prefixes(
    pieces: Pieces, model: UrdfModel, X_WM, X_M, where: str, joints: dict, name: str
) -> Claims | None:
    """Adds the course's pieces found in ``model``; the links they claim (the course's
    links of each piece, every link of a bin), or None when there are none."""
    names: list[str] = []
    prefixes: list[str] = []  # (a bin's: loaded with all its links)
    found = False
    for joint in model.joint_names():
        if joint.endswith("shoulder_pan_joint"):
            prefix = joint[: -len("shoulder_pan_joint")]
            _add_robot(pieces, model, prefix, X_WM, X_M, where, joints)
            names += [prefix + link for link in PIECE_LINKS["arm"]]
            for gripper in _gripper_prefixes(model, prefix):
                names += [gripper + link for link in PIECE_LINKS["gripper"]]
            found = True
    for link in model.links:
        if link.endswith("pedestal_link"):
            prefix = link[: -len("pedestal_link")]
            height = _box_height(model, link, where)
            pieces.pedestals[prefix] = ((X_WM @ X_M[link]).translation(), height, where)
            names += [prefix + link for link in PIECE_LINKS["pedestal"]]
            # As the student's file writes it (the cell's arm stands on it: pedestal_model).
            name = f"{prefix.rstrip('_')}_pedestal"
            pieces.own.append(
                OwnModel(name, own_links_urdf(model, [link], X_WM, joints, name), where, [0.0] * 6)
            )
        elif link.endswith("drop_point") and link[: -len("drop_point")] + "base_link" in X_M:
            prefix = link[: -len("drop_point")]
            pieces.bins.append(_bin(pieces, model, prefix, X_WM @ X_M[prefix + "base_link"], where, name))
            prefixes.append(prefix)
        elif link.endswith("optical_link"):
            _add_break_beam(pieces, model, link, X_WM @ X_M[link], where)
            names += [link[: -len("optical_link")] + suffix for suffix in PIECE_LINKS["break_beam"]]
        elif link != "workcell":
            continue
        found = True
    return Claims(frozenset(names), tuple(p for p in prefixes if p)) if found else None


def _bin(
    pieces: Pieces, model: UrdfModel, prefix: str, X_WB: RigidTransform, where: str, spawned: str
) -> dict:
    """The bin at ``prefix`` (in the model spawned as ``spawned``): a bin of box or mesh
    collisions is loaded as the student's file writes it, a model entry named as Gazebo
    names it (its walls give the cell's in-bin test and drop slots; its collision meshes
    convex pieces that keep it open, :mod:`~omtp_drake.launch.mesh_bins`); so is a bin
    with no collision at all, as Gazebo loads it (a part dropped in falls through; its
    visual's inside, where it can be measured, is the in-bin test); any other (other
    shapes, or a mesh nobody has), the catalogue's bin."""
    placed = _placed(prefix.rstrip("_"), X_WB, where)
    link = prefix + "base_link"
    walls = bin_walls(model, link)
    open_links: tuple[str, ...] = ()
    as_written = walls is not None
    if walls is None and not _has_collision(model, link):
        walls, as_written = mesh_bin_walls(model, link, pieces.packages, where, kind="visual"), True
        pieces.warnings.append(
            f"{where}: bin {placed['name']!r}: link {link!r} has no <collision>; loaded as written, "
            "as Gazebo does: a part dropped in falls through it"
        )
    elif walls is None and has_mesh_collision(model, link):
        walls, open_links = mesh_bin_walls(model, link, pieces.packages, where), (link,)
        as_written = walls is not None
        if walls is None:
            pieces.warnings.append(
                f"{where}: bin {placed['name']!r}: its collision meshes cannot be read or hold no "
                "floor and walls around its axis; the catalogue's bin stands in"
            )
    elif walls is None:
        pieces.warnings.append(_catalogue_bin_line(model, link, placed["name"], where))
    if as_written:
        taken = {placed["name"], *(own.name for own in pieces.own)}
        name = spawned if spawned and spawned not in taken else f"{placed['name']}_model"
        placed.update(model=name, walls=walls or [])
        text = piece_urdf(model, prefix + "base_link", prefix, name)
        pose = [*placed["xyz"], 0.0, 0.0, placed["yaw"]]
        pieces.own.append(OwnModel(name, text, where, pose, static=False, open_links=open_links))
    return placed


def _has_collision(model: UrdfModel, link: str) -> bool:
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    return element is not None and element.find("collision") is not None


def _catalogue_bin_line(model: UrdfModel, link: str, name: str, where: str) -> str:
    """The warning for a bin the cell cannot take as written (collisions that are neither
    a box floor and walls nor meshes): Gazebo loads it as it is."""
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    collisions = element.findall("collision") if element is not None else []
    shapes = sorted({g.tag for c in collisions for g in c.findall("geometry/*")})
    what = f"link {link!r}'s collisions ({', '.join(shapes) or 'no geometry'}) are no box floor and walls"
    return f"{where}: bin {name!r}: {what}; the catalogue's bin stands in"


def _gripper_prefixes(model: UrdfModel, prefix: str) -> list[str]:
    """The prefix of the gripper on the arm's tool0 (the cell builds it with the arm)."""
    tool = prefix + "tool0"
    return [
        j.child[: -len("base_link")]
        for j in model.joints.values()
        if j.parent == tool
        and j.child.endswith("base_link")
        and j.child[: -len("base_link")] + "suction_cup" in model.links
    ]


def _yaw_only(X: RigidTransform, what: str, where: str) -> float:
    roll, pitch, yaw = RollPitchYaw(X.rotation()).vector()
    if abs(roll) > _TOL or abs(pitch) > _TOL:
        raise WorkspaceError(
            f"{where}: {what} is tilted (roll {roll:.4f}, pitch {pitch:.4f}); the cell stands it upright"
        )
    return float(yaw)


def _placed(name: str, X_WB: RigidTransform, where: str) -> dict:
    return {"name": name, "xyz": [float(v) for v in X_WB.translation()], "yaw": _yaw_only(X_WB, name, where)}


def _add_robot(pieces, model: UrdfModel, prefix: str, X_WM, X_M, where: str, joints: dict) -> None:
    elbow = model.joints.get(prefix + "elbow_joint")
    if elbow is None or prefix + "base_link" not in X_M or prefix + "tool0" not in X_M:
        raise WorkspaceError(f"{where}: arm {prefix!r} lacks the UR links (base_link, elbow_joint, tool0)")
    length = float(np.linalg.norm(elbow.X_PJ.translation()[[0, 2]]))
    kinds = [k for k, v in UR_UPPER_ARMS.items() if abs(v - length) < _TOL]
    if not kinds:
        raise WorkspaceError(
            f"{where}: arm {prefix!r} has an upper arm of {length:.4f} m; supported: "
            + ", ".join(f"{k} ({v} m)" for k, v in UR_UPPER_ARMS.items())
        )
    name = prefix.rstrip("_")
    X_WB = X_WM @ X_M[prefix + "base_link"]
    digits = re.sub(r"\D", "", name)
    robot = {
        "name": name,
        "model": kinds[0],
        "xy": [float(v) for v in X_WB.translation()[:2]],
        "pedestal_height": float(X_WB.translation()[2]),
        "yaw": _yaw_only(X_WB, f"arm {name}", where),
        "pose_prefix": f"R{digits}" if digits else RobotConfig().pose_prefix,
        "initial_pose": RobotConfig().initial_pose,
        "gripper": _gripper(pieces, model, prefix, where, name),
    }
    limits, lines = arm_joint_limit(model, prefix, where)
    rates, rate_lines = arm_joint_rates(model, prefix, kinds[0], where)
    inertials, inertial_lines = arm_inertials(model, prefix, kinds[0], where)
    bare, bare_lines = gripper_collision(model, prefix, where)
    pieces.warnings += lines + rate_lines + inertial_lines + bare_lines
    robot.update(bare)
    robot.update(limits, **rates, **inertials)
    if any(j.startswith(prefix) for j in joints):
        given = " ".join(f"-J {k} {v}" for k, v in joints.items())
        pieces.warnings.append(
            f"{where}: spawn_model {given}: the arm starts at its named pose "
            f"{robot['pose_prefix']}{robot['initial_pose']} instead"
        )
    pieces.robots.append(robot)


def arm_joint_limit(model: UrdfModel, prefix: str, where: str) -> tuple[dict, list[str]]:
    """The arm's joint position limits as its URDF writes them, as the scenario's robot
    fields: ``joint_limit`` when one symmetric limit holds every joint (none when it is the
    course's pi), ``joint_limits`` when each has its own symmetric one (ur_description's
    unlimited arm: 2 pi, its elbow pi); and a warning line for limits that are not
    symmetric (the cell's arm, its servo and MoveIt's bounds take symmetric ones: the
    course's are kept)."""
    root = model.root_element
    limits = {}
    for name in PIECE_JOINTS:
        element = root.find(f"joint[@name='{prefix}{name}']/limit") if root is not None else None
        if element is None:
            continue
        try:
            limits[name] = (float(element.get("lower", "nan")), float(element.get("upper", "nan")))
        except ValueError:
            limits[name] = (math.nan, math.nan)
    if not limits:
        return {}, []
    uppers = [round(upper, 9) for _, upper in limits.values()]
    symmetric = all(abs(lower + upper) < 1e-9 for lower, upper in limits.values())
    if symmetric and len(limits) == len(PIECE_JOINTS) and all(0 < u <= 2 * math.pi + 1e-9 for u in uppers):
        uppers = [min(u, 2 * math.pi) for u in uppers]
        if len(set(uppers)) > 1:
            return {"joint_limits": uppers}, []
        return ({} if abs(uppers[0] - math.pi) < 1e-9 else {"joint_limit": uppers[0]}), []
    written = ", ".join(f"{name} [{lo:g}, {up:g}]" for name, (lo, up) in limits.items())
    return {}, [
        f"{where}: arm {prefix.rstrip('_')!r}: joint limits {written} are not symmetric limits in "
        f"(0, 2 pi] of its six joints; the cell's arm takes those and keeps the course's +/-{math.pi:g}"
    ]


def gripper_collision(model: UrdfModel, prefix: str, where: str) -> tuple[dict, list[str]]:
    """``gripper_collision: False`` and one warning line where the gripper on the arm's
    tool0 has no ``<collision>`` in its links (``base_link``, ``suction_cup``): loaded as
    written, nothing touches its cup, and the course's VacuumGripperPlugin, which attaches
    on contacts of its ``suction_cup_link``'s collisions (none: it never sees one), grasps
    nothing, as in Gazebo."""
    root = model.root_element
    for joint in model.joints.values():
        if root is None or joint.parent != prefix + "tool0" or not joint.child.endswith("base_link"):
            continue
        gripper = joint.child[: -len("base_link")]
        links = [gripper + link for link in PIECE_LINKS["gripper"]]
        if links[1] not in model.links or any(
            root.find(f"link[@name='{n}']/collision") is not None for n in links
        ):
            continue
        return {"gripper_collision": False}, [
            f"{where}: gripper {gripper.rstrip('_')!r}: its links {', '.join(links)} have no <collision>; "
            "loaded as written, nothing touches its cup, and its ROSVacuumGripperPlugin (which attaches on "
            "contacts of its suction cup link's collisions) grasps nothing, as in Gazebo"
        ]
    return {}, []


def _gripper(pieces: Pieces, model: UrdfModel, prefix: str, where: str, robot: str) -> str:
    """The gripper on the arm's tool0 (its name, '' for none); its plugin's attach rule and
    ROS names (the plugin whose ``suction_cup_link`` is this gripper's cup, or the only one)."""
    tool = prefix + "tool0"
    for joint in model.joints.values():
        if joint.parent == tool and joint.child.endswith("base_link"):
            gripper = joint.child[: -len("base_link")]
            if gripper + "suction_cup" not in model.links:
                continue
            plugins = [p for ref, g in model.gazebo for p in plugins_in(g, where, ref) if p.kind == "suction"]
            cup = gripper + "suction_cup"
            plugins = [p for p in plugins if p.text("suction_cup_link") in (None, cup)] or plugins
            if not plugins:
                pieces.warnings.append(
                    f"{where}: gripper {gripper.rstrip('_')!r} has no ROSVacuumGripperPlugin"
                )
            for plugin in plugins:
                checks = suction_checks(plugin)
                if pieces.suction_checks not in (None, checks):
                    raise WorkspaceError(f"{where}: the grippers' attach_steps differ; the cell has one rule")
                pieces.suction_checks = checks
            if len(plugins) > 1:
                raise WorkspaceError(
                    f"{where}: gripper {gripper.rstrip('_')!r} has {len(plugins)} "
                    "ROSVacuumGripperPlugins; valid: one"
                )
            if plugins:
                pieces.plugin_names["grippers"].append(gripper_names(plugins[0], robot))
            return gripper.rstrip("_")
    return ""


def _box_height(model: UrdfModel, link: str, where: str) -> float:
    root = model.root_element
    element = root.find(f"link[@name='{link}']") if root is not None else None
    box = element.find("collision/geometry/box") if element is not None else None
    if box is None and element is not None:
        box = element.find("visual/geometry/box")
    if box is None:
        raise WorkspaceError(f"{where}: pedestal {link!r} has no box to take its height from")
    try:
        return float(box.get("size", "").split()[2])
    except (IndexError, ValueError):
        raise WorkspaceError(
            f"{where}: pedestal {link!r} box size {box.get('size')!r} needs 3 numbers"
        ) from None


def _add_break_beam(pieces: Pieces, model: UrdfModel, link: str, X_WO: RigidTransform, where: str) -> None:
    plugins = [p for ref, g in model.gazebo if ref == link for p in plugins_in(g, where, ref)]
    beams = [p for p in plugins if p.kind == "break_beam"]
    if not beams:
        pieces.warnings.append(f"{where}: {link!r} has no ROSProximityRayPlugin; no break beam added")
        return
    for plugin in beams:
        check_break_beam(plugin)
        pieces.plugin_names.update(beam_names(plugin))
    # The cell's beam leaves its optical link along +x, an offset along x from its base.
    X_BO = RigidTransform([model_dimensions("break_beam.urdf.xacro")["optical_offset"], 0, 0])
    X_WB = X_WO @ X_BO.inverse()
    p_error = float(np.linalg.norm(X_WB.translation() - X_W_BREAK_BEAM.translation()))
    angle = float(abs((X_WB.rotation().inverse() @ X_W_BREAK_BEAM.rotation()).ToAngleAxis().angle()))
    if p_error > _TOL or angle > _TOL:  # the student moved it: it senses where it now stands
        xyz, rpy = X_WB.translation(), RollPitchYaw(X_WB.rotation()).vector()
        pieces.break_beam_pose = [round(float(v), 9) for v in [*xyz, *rpy]]
    pieces.break_beam = True


def merge_pedestals(pieces: Pieces) -> None:
    """Each pedestal stands under its arm; a pedestal whose height differs from the arm's
    base height is one warning (the cell stands the arm on top of its pedestal)."""
    by_name = {r["name"]: r for r in pieces.robots}
    for prefix, (p_W, height, where) in pieces.pedestals.items():
        robot = by_name.get(prefix.rstrip("_"))
        if robot is None:
            pieces.warnings.append(
                f"{where}: pedestal {prefix}pedestal_link has no arm {prefix.rstrip('_')!r}"
            )
            continue
        if float(np.hypot(*(np.asarray(robot["xy"]) - p_W[:2]))) > _TOL:
            raise WorkspaceError(
                f"{where}: pedestal {prefix}pedestal_link at {np.round(p_W[:2], 4).tolist()} is not under "
                f"arm {robot['name']} at {robot['xy']}; the cell stands each arm on its pedestal"
            )
        robot["pedestal_model"] = f"{prefix.rstrip('_')}_pedestal"
        if not math.isclose(height, robot["pedestal_height"], abs_tol=_TOL):
            pieces.warnings.append(
                f"{where}: pedestal {prefix}pedestal_link is {height:g} m high and arm {robot['name']} "
                f"stands at {robot['pedestal_height']:g} m; both as the files put them"
            )
