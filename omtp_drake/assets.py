"""Model files: the project's xacro sources and the classic UR arms.

Two sources of models feed the factory:

* ``models/*.xacro`` (shipped with this package): every piece of the cell built
  from primitives. They are expanded with the PyPI ``xacro`` package, without
  ROS: they include each other by paths relative to the including file, so no
  ``$(find PKG)`` (which needs the ament index) is involved.
* The classic UR5 / UR10 of the installed ``example-robot-data`` package. Drake
  1.51 cannot use them as shipped (``.stl`` collision meshes are rejected,
  Meshcat does not draw ``.stl``, ``.dae`` doubles the replay size, the URDF
  welds ``base_link`` to a ``world`` link). :func:`ur_urdf` converts the meshes
  once (``.stl`` -> ``.obj``, ``.dae`` -> ``.gltf``), writes a URDF whose link
  and joint names carry a prefix (``robot1_base_link``), and caches both under
  :func:`cache_dir`. Nothing converted is committed to the repository.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import logging
import math
import os
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

from omtp_drake.errors import ConfigError, UnknownNameError

_log = logging.getLogger(__name__)

#: The repository folder of model sources (``models/``).
MODELS_DIR = Path(__file__).resolve().parent.parent / "models"

#: Arms this project can load, by the name used in scenarios.
UR_MODELS = ("ur5", "ur10")

# Bump when the conversion below changes, so stale caches are not reused.
_CONVERTER_VERSION = "3"
_DRAKE_NS = "http://drake.mit.edu"


# ----------------------------------------------------------------------------
# xacro without ROS


def expand_xacro(path: Path | str, args: Mapping[str, object] | None = None) -> str:
    """Expands the xacro file ``path`` with ``args`` and returns the URDF text."""
    import xacro

    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"xacro file {str(path)!r} does not exist")
    mappings = {k: _xacro_value(v) for k, v in (args or {}).items()}
    try:
        doc = xacro.process_file(str(path), mappings=mappings)
    except xacro.XacroException as e:
        raise ConfigError(f"cannot expand {path.name} with {mappings}: {e}") from e
    return doc.toprettyxml(indent="  ")


@functools.cache
def model_dimensions(file: str) -> Mapping[str, float]:
    """The numeric ``<xacro:property name=... value=...>`` of ``models/<file>``.

    The model files are the one home of the cell's fixed sizes (a bin's walls,
    the belt's width and height); code that needs one reads it here instead of
    restating it.
    """
    path = MODELS_DIR / file
    if not path.is_file():
        raise UnknownNameError("model file", file, sorted(p.name for p in MODELS_DIR.glob("*.xacro")))
    tag = "{http://www.ros.org/wiki/xacro}property"
    values = {}
    for element in ET.parse(path).getroot().iter(tag):
        try:
            values[element.attrib["name"]] = float(element.attrib.get("value", ""))
        except ValueError:
            continue  # an expression, not a number
    return values


def _xacro_value(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return " ".join(repr(float(x)) for x in v)
    return str(v)


# ----------------------------------------------------------------------------
# Cache


#: A folder of this process's own where the cache entries it lacks are written, when the
#: shared cache is read-only to it (a graded run: the grader fills the shared cache before
#: the run starts, see :mod:`omtp_drake.grading.isolation`).
CACHE_LAYER_ENV = "OMTP_DRAKE_CACHE_LAYER"


def cache_dir() -> Path:
    """Folder of converted models: ``$OMTP_DRAKE_CACHE`` or ``~/.cache/omtp_drake``
    (created here unless it is read-only to this process, ``$OMTP_DRAKE_CACHE_LAYER``)."""
    root = os.environ.get("OMTP_DRAKE_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "omtp_drake"
    )
    key = hashlib.sha1(f"{_erd_version()}/{_CONVERTER_VERSION}".encode()).hexdigest()[:10]
    path = Path(root) / f"models-{key}"
    if not os.environ.get(CACHE_LAYER_ENV) and not path.is_dir():
        path.mkdir(parents=True, exist_ok=True)
    return path


def cache_entry(relative: str | Path) -> Path:
    """Where the cache's entry ``relative`` (a file or a folder) is, or is to be written,
    its parent folder made: in :func:`cache_dir`, unless that is read-only to this
    process (``$OMTP_DRAKE_CACHE_LAYER``) and lacks it: then in that layer. Nothing is
    written, not even a folder, for an entry the cache holds."""
    root = cache_dir()
    layer = os.environ.get(CACHE_LAYER_ENV)
    path = root / relative
    if layer and not path.exists():
        path = Path(layer) / root.name / relative
    if not path.parent.is_dir():
        path.parent.mkdir(parents=True, exist_ok=True)
    return path


def write_atomic(path: Path, data: bytes) -> None:
    """Writes ``data`` so concurrent readers never see a half-written file."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".")
    with os.fdopen(fd, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


# ----------------------------------------------------------------------------
# UR arms from example-robot-data


@functools.cache
def _erd_version() -> str:
    return importlib.metadata.version("example-robot-data")


@functools.cache
def ur_description_dir() -> Path:
    """The installed ``ur_description`` folder of ``example-robot-data``."""
    dist = importlib.metadata.distribution("example-robot-data")
    path = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots/ur_description")))
    if not (path / "urdf").is_dir():
        raise ConfigError(f"example-robot-data is installed but has no ur_description at {path}")
    return path


def _convert_mesh(src: Path, dst: Path) -> None:
    """Converts one mesh: ``.stl`` -> ``.obj`` (collision), ``.dae`` -> ``.gltf`` (visual)."""
    import trimesh

    if dst.suffix == ".obj":
        mesh = trimesh.load(src, force="mesh")
        write_atomic(dst, mesh.export(file_type="obj").encode())
        return
    scene = trimesh.load(src, force="scene")
    # glTF is y-up: Drake turns a glTF +90 deg about x when loading it, so
    # pre-rotate -90 deg about x to keep the link's own z-up geometry.
    scene.apply_transform(trimesh.transformations.rotation_matrix(-math.pi / 2, [1, 0, 0]))
    files = trimesh.exchange.gltf.export_gltf(scene, embed_buffers=True)
    write_atomic(dst, files["model.gltf"])


def _mesh_sources(model: str) -> list[tuple[Path, str]]:
    """The meshes of ``model``: (its source file, its converted file's entry in the cache)."""
    src_root = ur_description_dir() / "meshes" / model
    found = []
    for kind, src_ext, dst_ext in (("collision", ".stl", ".obj"), ("visual", ".dae", ".gltf")):
        for src in sorted((src_root / kind).glob(f"*{src_ext}")):
            found.append((src, f"{model}/{kind}/{src.stem}{dst_ext}"))
    return found


def _converted_mesh(entry: str, src: Path) -> Path:
    """The converted mesh ``entry`` of the cache (converted from ``src`` once)."""
    dst = cache_entry(entry)
    if not dst.exists():
        _log.info("converting %s -> %s", src, dst)
        _convert_mesh(src, dst)
    return dst


def ur_urdf(model: str, prefix: str, *, joint_limit: float = math.pi) -> Path:
    """A Drake-ready URDF of a classic UR arm, with every link and joint prefixed.

    Args:
        model: ``"ur5"`` or ``"ur10"``.
        prefix: prepended to link, joint and actuator names (``"robot1_"``).
        joint_limit: symmetric position limit of every joint (the course: pi).

    The ``world`` link and its joint are dropped (the station welds
    ``<prefix>base_link`` where it belongs), ``ee_link``'s 1 cm collision box is
    removed, collision meshes are declared convex and mesh paths point into the
    cache. The robot is named ``prefix`` without its trailing underscore.
    """
    if model not in UR_MODELS:
        raise UnknownNameError("arm model", model, UR_MODELS)
    src = ur_description_dir() / "urdf" / f"{model}_robot.urdf"
    name = prefix.rstrip("_") or model
    dst = cache_entry(f"{name}_{model}_{_limit_tag(joint_limit)}.urdf")
    if dst.exists() and all(cache_entry(entry).exists() for _, entry in _mesh_sources(model)):
        return dst
    meshes = {entry: _converted_mesh(entry, mesh) for mesh, entry in _mesh_sources(model)}

    ET.register_namespace("drake", _DRAKE_NS)
    root = ET.parse(src).getroot()
    root.set("name", name)
    _drop_world_and_ee_collision(root)
    _prefix_names(root, prefix, joint_limit)
    _point_meshes_to(root, model, meshes)
    write_atomic(dst, ET.tostring(root, encoding="utf-8", xml_declaration=True))
    return dst


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


def _prefix_names(root: ET.Element, prefix: str, joint_limit: float) -> None:
    """Prefixes link, joint, transmission and actuator names; sets revolute limits to +/- ``joint_limit``."""
    for link in root.findall("link"):
        link.set("name", prefix + _attr(link, "name"))
    for joint in root.findall("joint"):
        joint.set("name", prefix + _attr(joint, "name"))
        for tag in ("parent", "child"):
            el = _child(joint, tag)
            el.set("link", prefix + _attr(el, "link"))
        limit = joint.find("limit")
        if limit is not None and joint.get("type") == "revolute":
            limit.set("lower", repr(-joint_limit))
            limit.set("upper", repr(joint_limit))
    for trans in root.findall("transmission"):
        trans.set("name", prefix + _attr(trans, "name"))
        trans_joint = _child(trans, "joint")
        trans_joint.set("name", prefix + _attr(trans_joint, "name"))
        actuator = _child(trans, "actuator")
        actuator.set("name", prefix + _attr(actuator, "name"))


def _point_meshes_to(root: ET.Element, model: str, meshes: Mapping[str, Path]) -> None:
    """Points every mesh at its converted file (``meshes``: by its entry in the cache);
    collision meshes are declared convex."""
    for mesh in root.iter("mesh"):
        filename = _attr(mesh, "filename")
        kind = "collision" if "/collision/" in filename else "visual"
        stem = Path(filename).stem
        ext = ".obj" if kind == "collision" else ".gltf"
        entry = f"{model}/{kind}/{stem}{ext}"
        if entry not in meshes:
            raise ConfigError(f"UR model {model}: {filename!r} is none of its meshes {sorted(meshes)}")
        mesh.set("filename", str(meshes[entry]))
        if kind == "collision":
            ET.SubElement(mesh, f"{{{_DRAKE_NS}}}declare_convex")


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


def _limit_tag(limit: float) -> str:
    return f"lim{round(limit * 1e4)}"
