"""rclpy type support for the interface packages no PyPI wheel ships (``gazebo_msgs``'s entity
services and states, ``control_msgs``' FollowJointTrajectory, ``tf2_msgs``' TFMessage: what the
cell serves, and what a peer needs to read its Cyclone-written topics with rclpy), built once into
the model cache from the definitions in ``interfaces/`` (written here, fields as the ROS 2
packages declare them, so type names and hashes are theirs).

The build is what ``rosidl_generate_interfaces`` does under colcon, without colcon or
CMake: the rosidl generators rclpy's wheels bring (``rosidl_adapter``, ``rosidl_generator_c``
and ``_py``, ``rosidl_typesupport_c``, ``_fastrtps_c``, ``_introspection_c``) write the C
sources, and the system's C and C++ compilers build them against the wheels' headers and
libraries. It runs on first use, not at install: the generators and headers come with the
``ros2`` extra, which pip installs after this package's own build. Nothing downloads.

The result is a Python package folder (``import gazebo_msgs.srv``) whose ``__init__`` loads
its own libraries, so that rosidl's type support dispatch (``dlopen`` by library name) finds
them without ``LD_LIBRARY_PATH``. :func:`interfaces_path` gives that folder for
``sys.path`` or a process's ``PYTHONPATH``.
"""

from __future__ import annotations

import compileall
import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from collections.abc import Callable
from pathlib import Path

from omtp_drake.assets import cache_entry
from omtp_drake.errors import OmtpError

#: The packages built here, each with the packages its definitions use.
PACKAGES = {
    "gazebo_msgs": ("builtin_interfaces", "geometry_msgs", "std_msgs", "service_msgs"),
    "tf2_msgs": ("builtin_interfaces", "geometry_msgs", "std_msgs"),
    "control_msgs": (
        "builtin_interfaces",
        "geometry_msgs",
        "std_msgs",
        "trajectory_msgs",
        "action_msgs",
        "unique_identifier_msgs",
        "service_msgs",
    ),
}
DEFINITIONS = Path(__file__).resolve().parent / "interfaces"
#: The middleware type supports built (Fast DDS's, and the introspection one rclpy's
#: serialization and the dynamic type support use); ``rosidl_typesupport_c`` dispatches.
TYPESUPPORTS = ("rosidl_typesupport_fastrtps_c", "rosidl_typesupport_introspection_c")


class InterfacesUnavailable(OmtpError):
    """The interface packages cannot be built here (no compiler, or the build failed)."""


def interfaces_path() -> Path:
    """The folder holding the built packages (one per :data:`PACKAGES`), built on first use.

    Raises :class:`InterfacesUnavailable` naming what is missing."""
    folder = cache_entry(f"ros2_interfaces/{_key()}")
    if (folder / "COMPLETE").is_file():
        return folder
    missing = [tool for tool in ("cc", "c++") if shutil.which(tool) is None]
    if missing:
        raise InterfacesUnavailable(
            f"no {' or '.join(missing)} compiler on PATH to build {', '.join(PACKAGES)} "
            "type support (Debian: apt-get install gcc g++)"
        )
    # One build at a time per cache (pytest-xdist workers, two cells): the next one waits for it.
    with open(folder.parent / f"{folder.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / "COMPLETE").is_file():
            _build_all(folder)
    return folder


def _build_all(folder: Path) -> None:
    """Every package of :data:`PACKAGES` into ``folder``, which appears whole or not at all."""
    staged = Path(tempfile.mkdtemp(dir=folder.parent, prefix=folder.name + "."))
    staged.chmod(0o755)  # readable as the cache's other entries (a shared, read-only cache layer)
    try:
        for package in PACKAGES:
            _build(package, staged)
        shutil.rmtree(staged / "build")
        # Their bytecode too (~120 kB of generated Python): every process that imports them (a
        # ros2 cell, a student's node) compiled it again where nothing writes bytecode
        # (PYTHONDONTWRITEBYTECODE=1, a read-only cache): ~0.1 CPU s a process.
        compileall.compile_dir(staged, quiet=1)
        (staged / "COMPLETE").write_text("")
        os.rename(staged, folder)
    finally:
        shutil.rmtree(staged, ignore_errors=True)


def activate() -> Path:
    """Builds (once) and puts the packages on ``sys.path``, and on ``PYTHONPATH`` for the
    processes this one starts (a launch file's own nodes import them as under ``ros2 launch``
    with the packages installed); returns their folder."""
    folder = interfaces_path()
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    if str(folder) not in paths:
        os.environ["PYTHONPATH"] = os.pathsep.join([str(folder), *paths])
    return folder


def activated(missing: str, warn: Callable[[str], None]) -> bool:
    """:func:`activate`, True; or, where the packages cannot be built, ``warn("<missing>: <why>")``
    (what is off without them, and why) and False: the one rule of every server needing them."""
    try:
        activate()
    except InterfacesUnavailable as e:
        warn(f"{missing}: {e}")
        return False
    return True


def _key() -> str:
    """Changes with the definitions, this recipe, the interpreter, the venv and the rosidl versions."""
    from importlib.metadata import version

    digest = hashlib.sha1()
    for recipe in ("interface_build.py", "interface_generate.py"):
        digest.update((Path(__file__).parent / recipe).read_bytes())
    for path in sorted(DEFINITIONS.rglob("*.*")):
        digest.update(str(path.relative_to(DEFINITIONS)).encode() + path.read_bytes())
    for dist in ("ros-rclpy", "ros-rosidl-generator-py", "ros-rosidl-typesupport-fastrtps-c"):
        digest.update(version(dist).encode())
    digest.update(f"{sys.prefix}|{sys.version}".encode())
    return digest.hexdigest()[:12]


def _run(command: list[str], package: str, step: str, env: dict[str, str] | None = None) -> None:
    done = subprocess.run(command, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        tail = "\n".join((done.stderr or done.stdout).strip().splitlines()[-12:])
        raise InterfacesUnavailable(f"building {package} type support failed at {step}:\n{tail}")


def _build(package: str, out: Path) -> None:
    """Generates ``package``'s sources into ``out/build`` and its Python package into ``out``."""
    gen = out / "build" / package
    env = dict(os.environ, AMENT_PREFIX_PATH=sys.prefix)
    generate = [sys.executable, "-m", "omtp_drake.ros2.interface_generate", package]
    _run([*generate, str(DEFINITIONS / package), str(gen), str(out / package)], package, "rosidl", env)
    _compile(package, gen, out / package)


def _compile(package: str, gen: Path, target: Path) -> None:
    """The libraries ``rosidl_generate_interfaces`` links, with its names, into ``target``; then
    the Python extension modules and the package's ``__init__``."""
    prefix = Path(sys.prefix)
    include = prefix / "include"
    flags = [f"-I{gen / part}" for part in ("c", "typesupport_c", *TYPESUPPORTS)]
    flags += [f"-I{include}", *(f"-I{d}" for d in sorted(include.iterdir()) if d.is_dir())]
    flags += [f"-I{sysconfig.get_paths()['include']}", f"-I{_numpy_include()}"]
    flags += [f"-L{prefix / 'lib'}", f"-L{target}", f"-Wl,-rpath,$ORIGIN:{prefix / 'lib'}"]
    for name, sources, libs in _libraries(package, gen, target):
        compiler = "c++" if any(s.suffix == ".cpp" for s in sources) else "cc"
        module = not name.startswith("lib")
        command = [compiler, "-shared", "-fPIC", "-O1", "-w", *map(str, sources), "-o", str(target / name)]
        command += [*flags, *([] if module else [f"-Wl,-soname,{name}"]), *(f"-l{n}" for n in libs)]
        _run(command, package, name)
    _write_init(package, target)


def _libraries(package: str, gen: Path, target: Path) -> list[tuple[str, list[Path], list[str]]]:
    """(file name, sources, libraries it links) of each library, in build order."""
    deps = PACKAGES[package]

    def sources(part: str, suffix: str) -> list[Path]:
        return sorted((gen / part).rglob(f"*{suffix}"))

    def of_deps(kind: str) -> list[str]:
        return [f"{d}__{kind}" for d in deps]

    c_lib, ts_c, py_lib = (f"{package}__rosidl_{k}" for k in ("generator_c", "typesupport_c", "generator_py"))
    built = [
        (
            f"lib{c_lib}.so",
            sources("c", ".c"),
            [*of_deps("rosidl_generator_c"), "rosidl_runtime_c", "rcutils"],
        )
    ]
    for ts in TYPESUPPORTS:
        fastrtps = "fastrtps" in ts
        extra = ["rosidl_typesupport_fastrtps_cpp", "fastcdr", "rmw"] if fastrtps else []
        libs = [c_lib, *of_deps(ts), ts, *extra, "rosidl_runtime_c"]
        built.append((f"lib{package}__{ts}.so", sources(ts, ".cpp" if fastrtps else ".c"), libs))
    libs = [c_lib, *of_deps("rosidl_typesupport_c"), "rosidl_typesupport_c", "rosidl_runtime_c"]
    built.append((f"lib{ts_c}.so", sources("typesupport_c", ".cpp"), libs))
    py_sources = [s for s in sorted(target.rglob("*_s.c")) if ".ep." not in s.name]
    libs = [c_lib, ts_c, *of_deps("rosidl_generator_py"), *of_deps("rosidl_generator_c"), "rosidl_runtime_c"]
    built.append((f"lib{py_lib}.so", py_sources, libs))
    for ts in ("rosidl_typesupport_c", *TYPESUPPORTS):
        entry = [target / f"_{package}_s.ep.{ts}.c"]
        libs = [py_lib, f"{package}__{ts}", ts_c, c_lib, "rosidl_runtime_c", "rosidl_typesupport_c"]
        built.append((f"{package}_s__{ts}.so", entry, libs))
    return built


def _numpy_include() -> str:
    import numpy

    return numpy.get_include()


def _write_init(package: str, target: Path) -> None:
    """The package's ``__init__``: loads its type support libraries globally, so the
    dispatch's ``dlopen("lib<package>__<typesupport>.so")`` finds them already loaded."""
    names = [f"lib{package}__{ts}.so" for ts in ("rosidl_generator_c", "rosidl_typesupport_c", *TYPESUPPORTS)]
    (target / "__init__.py").write_text(
        f'"""{package}: ROS 2 type support built by omtp_drake.ros2.interface_build."""\n'
        "import ctypes as _ctypes\nimport os as _os\n\n"
        f"for _name in {names!r}:\n"
        "    _ctypes.CDLL(_os.path.join(_os.path.dirname(__file__), _name), mode=_ctypes.RTLD_GLOBAL)\n"
    )
