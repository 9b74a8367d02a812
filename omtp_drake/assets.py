"""Model files: the project's xacro sources, any description's meshes, the model cache.

Two sources of models feed the factory, and a student's own descriptions join them:

* ``models/*.xacro`` (shipped with this package): every piece of the cell built
  from primitives. They are expanded with the PyPI ``xacro`` package, without
  ROS: they include each other by paths relative to the including file, so no
  ``$(find PKG)`` (which needs the ament index) is involved.
* The classic UR5 / UR10 of the installed ``example-robot-data`` package. Drake
  1.51 cannot use them as shipped (``.stl`` collision meshes are rejected,
  Meshcat does not draw ``.stl``, ``.dae`` doubles the replay size, the URDF
  welds ``base_link`` to a ``world`` link). :func:`omtp_drake.ur_arms.ur_urdf` converts the meshes
  once (``.stl`` -> ``.obj``, ``.dae`` -> ``.gltf``), writes a URDF whose link
  and joint names carry a prefix (``robot1_base_link``), and caches both under
  :func:`cache_dir`. Nothing converted is committed to the repository.
* Any URDF or SDF (a student's robot, another vendor's description package):
  :func:`drake_ready_meshes` resolves each mesh URI as ROS and Gazebo do and points
  it at the file Drake reads (:func:`drake_mesh`: ``.stl``/``.dae``/``.glb``
  converted once, cached by the source's content hash; the UR arms use it too); a
  mesh nobody has is left out with one warning, as Gazebo does.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import importlib.metadata
import logging
import math
import os
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Collection, Mapping
from pathlib import Path

from omtp_drake.errors import ConfigError, UnknownNameError

_log = logging.getLogger(__name__)

#: The repository folder of model sources (``models/``).
MODELS_DIR = Path(__file__).resolve().parent.parent / "models"

#: Arms this project can load, by the name used in scenarios.
UR_MODELS = ("ur5", "ur10")

# Bump when the conversion below changes, so stale caches are not reused.
_CONVERTER_VERSION = "5"
_PIECES_VERSION = "4"  # (convex_piece_files)
DRAKE_NS = "http://drake.mit.edu"


# ----------------------------------------------------------------------------
# xacro without ROS


def expand_xacro(path: Path | str, args: Mapping[str, object] | None = None) -> str:
    """Expands the xacro file ``path`` with ``args`` and returns the URDF text."""
    import xacro

    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"xacro file {str(path)!r} does not exist")
    mappings = {k: _xacro_value(v) for k, v in (args or {}).items()}
    entry = _expansion_entry(path, mappings)
    if entry is not None and entry.is_file():
        return entry.read_text()
    try:
        doc = xacro.process_file(str(path), mappings=mappings)
    except xacro.XacroException as e:
        raise ConfigError(f"cannot expand {path.name} with {mappings}: {e}") from e
    text = urdf_text(doc)
    if entry is not None:
        write_atomic(entry, text.encode())
    return text


def _expansion_entry(path: Path, mappings: Mapping[str, str]) -> Path | None:
    """The model cache's entry for the expansion of the shipped model ``path`` with
    ``mappings`` (None for a file outside ``models/``). A cell's build expands about 27 of
    them, half its CPU (each graded run's too): the key is every ``models/`` file's content
    (they include each other), the xacro version, the file and its arguments."""
    if path.resolve().parent != MODELS_DIR:
        return None
    key = [xacro_version(), path.name, sorted(mappings.items()), _models_digest()]
    return cache_entry(f"xacro/{hashlib.sha1(repr(key).encode()).hexdigest()[:24]}.urdf")


def _models_digest() -> list[tuple[str, str]]:
    """Each ``models/`` file's name and content hash, in name order: one listing and one stat a
    file (the listing's entries; each expansion asks, 16 times a cell's build)."""
    files = sorted((entry for entry in os.scandir(MODELS_DIR) if entry.is_file()), key=lambda e: e.name)
    return [(e.name, _content_hash(e.path, st.st_mtime_ns, st.st_size)) for e in files for st in (e.stat(),)]


@functools.cache
def xacro_version() -> str:
    """The installed xacro's version (a part of every cached expansion's key)."""
    return importlib.metadata.version("xacro")


def urdf_text(doc) -> str:
    """The text of xacro's document ``doc``, which is then unlinked: a minidom tree is a web
    of parent links that only Python's cyclic collector frees, and the many trees of a
    launch's expansions made its slow full collections run mid-build (bench/README.md)."""
    try:
        return doc.toprettyxml(indent="  ")
    finally:
        doc.unlink()


@functools.cache
def model_dimensions(file: str) -> Mapping[str, float]:
    """The numeric ``<xacro:property name=... value=...>`` (and ``<xacro:arg default=...>``)
    of ``models/<file>``.

    The model files are the one home of the cell's fixed sizes (a bin's walls,
    the belt's width and height); code that needs one reads it here instead of
    restating it.
    """
    path = MODELS_DIR / file
    if not path.is_file():
        raise UnknownNameError("model file", file, sorted(p.name for p in MODELS_DIR.glob("*.xacro")))
    xacro = "{http://www.ros.org/wiki/xacro}"
    values = {}
    for element in ET.parse(path).getroot().iter():
        if element.tag not in (f"{xacro}property", f"{xacro}arg"):
            continue
        try:  # (an argument's default: the size a scenario may change)
            value = element.attrib.get("value", element.attrib.get("default", ""))
            values[element.attrib["name"]] = float(value)
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
# Meshes as Drake reads them

#: Mesh files a description may name (any case), as ROS packages and Gazebo models ship them.
MESH_EXTENSIONS = (".stl", ".dae", ".obj", ".gltf", ".glb")

#: URI schemes whose files are fetched from the internet by Gazebo (nobody has them offline).
_ONLINE = ("http://", "https://")


def drake_mesh(src: Path, *, collision: bool) -> Path:
    """The file Drake 1.51 reads for the mesh file ``src``.

    ``.obj`` and ``.gltf`` are read as they are. The rest is converted once and cached
    by the source's content (the same bytes anywhere are one conversion): ``.stl`` ->
    ``.obj``; ``.dae`` -> ``.gltf`` (a visual: colours and textures kept) or ``.obj`` (a
    collision: one mesh, its nodes' transforms applied); ``.glb`` -> ``.gltf``. A
    ``.dae``'s ``<unit meter>`` is applied, its ``<up_axis>`` is not (as Gazebo's
    Collada loader does). Raises ConfigError for another file type.
    """
    ext = src.suffix.lower()
    if ext not in MESH_EXTENSIONS:
        raise UnknownNameError(f"mesh file type of {src}", src.suffix, MESH_EXTENSIONS)
    if ext in (".obj", ".gltf"):
        return src
    target = ".gltf" if ext == ".glb" or (ext == ".dae" and not collision) else ".obj"
    stat = src.stat()
    digest = _content_hash(str(src), stat.st_mtime_ns, stat.st_size)
    dst = cache_entry(f"meshes/{digest}-{ext[1:]}{target}")
    if not dst.exists():
        _log.info("converting %s -> %s", src, dst)
        convert_mesh(src, dst)
    return dst


def file_hash(path: str | Path) -> str | None:
    """The hash of the bytes of the file ``path`` (None if it cannot be read)."""
    try:
        stat = os.stat(path)
        return _content_hash(str(path), stat.st_mtime_ns, stat.st_size)
    except OSError:
        return None


@functools.lru_cache(maxsize=4096)
def _content_hash(path: str, mtime_ns: int, size: int) -> str:
    """The hash of a file's bytes (remembered per path, modification time and size)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:24]


def convert_mesh(src: Path, dst: Path) -> None:
    """Writes ``src`` (``.stl``, ``.dae``, ``.glb``) as ``dst`` (``.obj`` or ``.gltf``)."""
    import trimesh

    ext = src.suffix.lower()
    try:
        scene = trimesh.load(str(src), file_type=ext[1:], force="scene")
    except Exception as e:  # trimesh and pycollada raise many types for a broken file
        raise ConfigError(f"{src}: not a readable {ext} mesh: {e}") from None
    if not scene.geometry:
        raise ConfigError(f"{src}: the {ext} file holds no mesh")
    if ext == ".dae":
        scene = scene.scaled(_collada_unit(src))
    if dst.suffix == ".obj":
        mesh = scene.to_mesh()
        # With its normals: Drake's VTK renderer (a camera's view) refuses an OBJ without them.
        write_atomic(dst, mesh.export(file_type="obj", include_texture=False, include_normals=True).encode())
        return
    if ext == ".dae":
        # glTF is y-up: Drake turns a glTF +90 deg about x when loading it, so turn the
        # z-up scene -90 deg about x first to keep the link's own geometry.
        scene.apply_transform(trimesh.transformations.rotation_matrix(-math.pi / 2, [1, 0, 0]))
    files = trimesh.exchange.gltf.export_gltf(scene, embed_buffers=True)
    write_atomic(dst, files["model.gltf"])


def obj_bounds(path: Path) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The (lo, hi) corners of the axis-aligned box of the vertices the faces of the
    ``.obj`` file ``path`` use (as trimesh's ``bounds``: a vertex no face uses is not
    counted), read as written (an OBJ has no transforms). Read here, not with trimesh,
    whose import (with scipy's spatial module) costs a command ~1 CPU s; ConfigError for a
    file whose faces use no vertex."""
    vertices: list[tuple[float, float, float]] = []
    used: set[int] = set()
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith("v "):
                x, y, z = line.split()[1:4]
                vertices.append((float(x), float(y), float(z)))
            elif line.startswith("f "):
                for corner in line.split()[1:]:
                    i = int(corner.split("/", 1)[0])
                    used.add(i - 1 if i > 0 else len(vertices) + i)  # (negative: relative)
    if not used:
        raise ConfigError(f"{path}: the mesh has no faces")
    points = [vertices[i] for i in sorted(used)]
    lo = tuple(min(p[k] for p in points) for k in range(3))
    hi = tuple(max(p[k] for p in points) for k in range(3))
    return lo, hi  # type: ignore[return-value]


def _collada_unit(src: Path) -> float:
    """Metres per unit of a Collada file (``<asset><unit meter=...>``; 1 without one)."""
    for _, element in ET.iterparse(src):
        if element.tag.rsplit("}", 1)[-1] == "unit":
            try:
                return float(element.get("meter", "1"))
            except ValueError:
                return 1.0
        if element.tag.rsplit("}", 1)[-1] == "asset":
            break
    return 1.0


def drake_ready_meshes(
    root: ET.Element, *, file: str, packages: Mapping[str, str], open_links: Collection[str] = ()
) -> None:
    """Every mesh of the URDF or SDF ``root`` pointed (in place) at the file Drake reads.

    Each ``<mesh filename=...>`` (URDF) or ``<mesh><uri>`` (SDF) is resolved as ROS and
    Gazebo resolve it (``package://`` and ``model://`` in ``packages``, ``file://``,
    absolute, or relative to ``file``'s folder), converted (:func:`drake_mesh`) and
    written back as a ``file://`` URI; its scale stays. A collision mesh is declared
    convex (Drake's point contact uses its convex hull) unless the collision asks for
    ``<drake:rigid_hydroelastic/>`` (then its own triangles). A mesh nobody has (a
    package or file not found, a URL, another file type) is left out with its visual or
    collision, one warning naming the URI and the folders searched, and the model loads
    without it, as Gazebo logs ``Unable to find uri`` and goes on; so is a file no mesh
    reader can read (the warning says why). The collision meshes of ``open_links`` (an open
    bin, whose convex hull would be a closed block) are their :func:`convex_piece_files`
    instead, each declared convex, with the mesh's origin and scale.
    """
    warned: set[str] = set()
    for link in list(root.iter()):
        for shape in list(link):
            mesh = shape.find("geometry/mesh") if shape.tag in ("visual", "collision") else None
            if mesh is None:
                continue
            uri = mesh.get("filename") if mesh.get("filename") is not None else mesh.findtext("uri")
            found = _drake_file((uri or "").strip(), packages, file, collision=shape.tag == "collision")
            if isinstance(found, str):
                if uri not in warned:
                    warned.add(uri or "")
                    _log.warning(
                        "%s: mesh %r %s; %s of %r left out, as Gazebo does",
                        file, uri, found, shape.tag, link.get("name"),
                    )  # fmt: skip
                link.remove(shape)
                continue
            if shape.tag == "collision" and link.get("name") in open_links:
                _split_collision(link, shape, found)
                continue
            _point_mesh(mesh, found)
            if shape.tag == "collision" and shape.find(_HYDRO_RIGID) is None:
                if mesh.find(f"{{{DRAKE_NS}}}declare_convex") is None:
                    ET.SubElement(mesh, f"{{{DRAKE_NS}}}declare_convex")


def convex_piece_files(obj: Path) -> list[tuple[Path, list[float]]]:
    """The convex pieces of the mesh ``obj`` that keep it open
    (:func:`omtp_drake.convex_pieces.write_pieces`): each an ``.obj`` and, when it is a box
    along the mesh's axes, its centre and size (else no numbers). Made once and cached by
    the mesh's content hash, as the converted meshes are."""
    stat = obj.stat()
    digest = _content_hash(str(obj), stat.st_mtime_ns, stat.st_size)
    index = cache_entry(f"meshes/{digest}-pieces{_PIECES_VERSION}/index.txt")
    if not index.exists():
        from omtp_drake.convex_pieces import write_pieces

        _log.info("cutting %s into convex pieces -> %s", obj, index.parent)
        write_pieces(obj, index, write_atomic)
    words = [line.split() for line in index.read_text().splitlines()]
    return [(index.parent / w[0], [float(v) for v in w[1:]]) for w in words]


def _split_collision(link: ET.Element, shape: ET.Element, obj: Path) -> None:
    """``shape`` (a collision of ``link``) replaced by one collision per convex piece of
    ``obj``, declared convex; in a URDF, a box piece is a ``<box>`` (its origin and size
    through the collision's origin and the mesh's scale: Drake's box contact is sturdier)."""
    at = list(link).index(shape)
    link.remove(shape)
    for k, (piece, box) in enumerate(convex_piece_files(obj)):
        collision = copy.deepcopy(shape)
        if collision.get("name"):
            collision.set("name", f"{collision.get('name')}_piece_{k}")
        geometry, mesh = collision.find("geometry"), collision.find("geometry/mesh")
        if geometry is None or mesh is None:
            continue
        if box and mesh.get("filename") is not None:  # (a URDF)
            scale = [float(v) for v in mesh.get("scale", "1 1 1").split()]
            geometry.remove(mesh)
            ET.SubElement(geometry, "box", size=" ".join(repr(v * s) for v, s in zip(box[3:], scale)))
            _shift_origin(collision, [c * s for c, s in zip(box[:3], scale)])
        else:
            _point_mesh(mesh, piece)
            ET.SubElement(mesh, f"{{{DRAKE_NS}}}declare_convex")
        link.insert(at + k, collision)


def _shift_origin(element: ET.Element, offset: list[float]) -> None:
    """Moves a URDF element's ``<origin>`` by ``offset`` (in its own frame)."""
    from pydrake.math import RigidTransform, RollPitchYaw

    origin = element.find("origin")
    origin = origin if origin is not None else ET.SubElement(element, "origin")
    rpy = RollPitchYaw([float(v) for v in origin.get("rpy", "0 0 0").split()])
    X = RigidTransform(rpy, [float(v) for v in origin.get("xyz", "0 0 0").split()]) @ RigidTransform(offset)
    origin.set("xyz", " ".join(repr(float(v)) for v in X.translation()))


def _drake_file(uri: str, packages: Mapping[str, str], file: str, *, collision: bool) -> Path | str:
    """The file Drake reads for a mesh URI, or why there is none."""
    src, searched = mesh_source(uri, packages, file)
    if src is None:
        return f"not found (searched: {searched})"
    if src.suffix.lower() not in MESH_EXTENSIONS:
        return f"is a {src.suffix} file (meshes: {', '.join(MESH_EXTENSIONS)})"
    try:
        return drake_mesh(src, collision=collision)
    except ConfigError as e:
        return f"cannot be read ({e})"


_HYDRO_RIGID = f"{{{DRAKE_NS}}}proximity_properties/{{{DRAKE_NS}}}rigid_hydroelastic"


def _point_mesh(mesh: ET.Element, path: Path) -> None:
    uri = path.resolve().as_uri()
    if mesh.get("filename") is not None:
        mesh.set("filename", uri)
    else:
        element = mesh.find("uri")
        element = element if element is not None else ET.SubElement(mesh, "uri")
        element.text = uri


def mesh_source(uri: str, packages: Mapping[str, str], file: str) -> tuple[Path | None, str]:
    """The file a mesh URI names (None: not found or not a mesh) and the folders searched."""
    base = Path(file).parent if file else Path.cwd()
    for scheme in ("package://", "model://"):
        if uri.startswith(scheme):
            name, _, rest = uri[len(scheme) :].partition("/")
            folder = packages.get(name)
            if folder is None:
                parents = sorted({str(Path(f).parent) for f in packages.values()})
                return None, f"no {scheme[:-3]} {name!r} in {', '.join(parents) or 'no folder'}"
            return _file_or_none(Path(folder) / rest), folder
    if uri.startswith(_ONLINE) or not uri:
        return None, "nothing offline"
    path = Path(uri[len("file://") :] if uri.startswith("file://") else uri)
    path = path if path.is_absolute() else base / path
    return _file_or_none(path), str(path.parent)


def _file_or_none(path: Path) -> Path | None:
    try:
        return path if path.is_file() else None
    except (OSError, ValueError):  # a name no file system takes (too long, a NUL byte)
        return None


@functools.cache
def _erd_version() -> str:
    return importlib.metadata.version("example-robot-data")
