"""xacro expanded with ``$(find PKG)`` resolved in a :class:`~omtp_drake.workspace.Workspace`.

The PyPI ``xacro`` resolves ``$(find PKG)`` as ROS 2 does: through
``ament_index_python``, which reads the ament resource index of each prefix in
``AMENT_PREFIX_PATH`` (``share/ament_index/resource_index/packages/PKG`` marks a
package, ``share/PKG`` is its folder). :func:`ament_prefix` writes such a prefix for a
workspace (a marker file and a ``share/PKG`` link to the package's folder per
package, catkin and colcon packages alike), once per set of package folders, and
:func:`expand_xacro_in` points ``AMENT_PREFIX_PATH`` at it while xacro runs. Nothing
of xacro is changed; the environment variable is process-wide, so expansions run one
at a time (a lock) and the variable is restored after each. The workspace's packages
are the only ones found (a ROS 2 install's ``AMENT_PREFIX_PATH`` is not searched), as
``package://`` URIs are resolved in the same workspace.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import tempfile
import threading
from collections.abc import Mapping
from contextlib import contextmanager
from pathlib import Path

from omtp_drake.errors import MissingPackageError, WorkspaceError
from omtp_drake.workspace.packages import Workspace

_XACRO_LOCK = threading.Lock()

#: ament's environment variable of install prefixes, read by ``ament_index_python``.
AMENT_PREFIX_PATH = "AMENT_PREFIX_PATH"

#: Bump when the prefix layout written below changes.
_INDEX_VERSION = "1"


def expand_xacro_in(
    workspace: Workspace, path: str | os.PathLike, args: Mapping[str, str] | None = None
) -> str:
    """The URDF text of the xacro (or plain URDF) file ``path`` with ``args``, its
    ``$(find PKG)`` resolved in ``workspace``.

    Raises MissingPackageError for a package the workspace does not have, and
    WorkspaceError naming the file for any other xacro error (a missing
    ``$(arg)``, a bad include, malformed XML).
    """
    path = Path(path)
    if not path.is_file():
        raise WorkspaceError(f"{path}: no such file")
    prefix = ament_prefix(workspace)
    key = (str(path.resolve()), tuple(sorted((args or {}).items())), str(prefix))
    known = _EXPANDED.get(key)
    if known is not None and all(_stamp(f) == stamp for f, stamp in known[1]):
        return known[0]
    kept = _kept_expansion(key)
    if kept is not None:  # (kept only if it passed _remember's check: not read again)
        _hold(key, *kept)
        return kept[0]
    import xacro  # (only to expand: a kept expansion needs none of it, 0.01 CPU s to import)

    with _XACRO_LOCK, environment_set(AMENT_PREFIX_PATH, str(prefix)):
        first = len(xacro.all_includes)
        try:
            doc = xacro.process_file(str(path), mappings=dict(args or {}))
        except Exception as e:
            raise _explained(workspace, path, e) from None
        read = [str(path.resolve()), *xacro.all_includes[first:]]
    try:
        text = doc.toprettyxml(indent="  ")
    finally:
        doc.unlink()  # freed now, not by the cyclic collector (as omtp_drake.assets.expand_xacro)
    text = _real_folders(text, prefix, workspace)
    if _remember(key, text, read):
        _keep_expansion(key, text, read)
    return text


#: Expansions of this process: (file, args, prefix) -> (text, the (file, stamp) of every file
#: xacro read). A launch's xacro commands run again at each build of its cell (a notebook's,
#: a batch's); the text is reused while none of the files changed. An expansion that reads
#: the environment (``$(env)``, ``$(optenv)``) is not kept.
_EXPANDED: dict[tuple, tuple[str, tuple[tuple[str, tuple[int, int] | None], ...]]] = {}
_EXPANDED_MAX = 64


def _stamp(file: str) -> tuple[int, int] | None:
    try:
        stat = os.stat(file)
    except OSError:
        return None
    return stat.st_mtime_ns, stat.st_size


def _remember(key: tuple, text: str, files: list[str]) -> bool:
    """Keeps the expansion ``key`` in this process; False for one that cannot be kept (it
    reads the environment, or a file it read is gone)."""
    for file in dict.fromkeys(files):
        try:
            source = Path(file).read_text(errors="replace")
        except OSError:
            return False
        if "$(env" in source or "$(optenv" in source:
            return False
    _hold(key, text, files)
    return True


def _hold(key: tuple, text: str, files: list[str]) -> None:
    """Holds the expansion ``key`` in this process, with the stamps of the files it read."""
    if len(_EXPANDED) >= _EXPANDED_MAX:
        _EXPANDED.pop(next(iter(_EXPANDED)))
    _EXPANDED[key] = (text, tuple((f, _stamp(f)) for f in dict.fromkeys(files)))


# The model cache keeps what _remember keeps, for the next process: a command's first build
# of a launch expanded its xacro files again (about 0.2 CPU s of a course launch's 0.5,
# bench/bench_launch.py --cold). An entry is the text and the content hash of every file
# xacro read (the file, its includes, its yaml); it is used while each hashes the same.


def _cache_file(key: tuple) -> Path:
    from omtp_drake.assets import cache_entry, xacro_version

    digest = hashlib.sha1(repr((xacro_version(), _INDEX_VERSION, key)).encode()).hexdigest()[:24]
    return cache_entry(f"xacro-in/{digest}.json")


def _kept_expansion(key: tuple) -> tuple[str, list[str]] | None:
    """(text, files read) of the cache's expansion ``key``, if every file still has the
    content it had."""
    from omtp_drake.assets import file_hash

    try:
        kept = json.loads(_cache_file(key).read_text())
        files = [(str(f), str(h)) for f, h in kept["files"]]
        text = str(kept["text"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if any(file_hash(f) != h for f, h in files):
        return None
    return text, [f for f, _ in files]


def _keep_expansion(key: tuple, text: str, files: list[str]) -> None:
    from omtp_drake.assets import file_hash, write_atomic

    hashes = [(f, file_hash(f)) for f in dict.fromkeys(files)]
    if any(h is None for _, h in hashes):
        return
    write_atomic(_cache_file(key), json.dumps({"files": hashes, "text": text}).encode())


def _real_folders(text: str, prefix: Path, workspace: Workspace) -> str:
    """``text`` with each ``$(find PKG)`` result (``PREFIX/share/PKG``, a link) written as the
    package's own folder, so the description names the student's files."""
    share = re.escape(str(prefix / "share")) + r"/([A-Za-z0-9_-]+)(?=[/\s\"'<]|$)"

    def folder(match: re.Match) -> str:
        found = workspace.packages.get(match.group(1))
        return str(Path(found).resolve()) if found is not None else match.group(0)

    return re.sub(share, folder, text)


def ament_prefix(workspace: Workspace) -> Path:
    """An ament install prefix whose resource index lists the workspace's packages.

    Written once per set of (name, folder) pairs under the temporary folder (the same
    pairs give the same prefix, in any process); a link per package, no copies.
    """
    given = (os.getcwd(), *workspace.packages.items())  # (a relative folder is the cwd's)
    known = _PREFIXES.get(given)
    if known is not None and known.is_dir():
        return known
    pairs = sorted((name, str(Path(folder).resolve())) for name, folder in workspace.packages.items())
    key = hashlib.sha1(repr((_INDEX_VERSION, pairs)).encode()).hexdigest()[:16]
    root = Path(tempfile.gettempdir()) / f"omtp_drake-ament-{os.getuid()}"
    prefix = root / key
    if prefix.is_dir():
        return _PREFIXES.setdefault(given, prefix)
    root.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(dir=root, prefix=f".{key}-"))
    index = staging / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    for name, folder in pairs:
        (index / name).write_text("")
        (staging / "share" / name).symlink_to(folder, target_is_directory=True)
    try:
        staging.rename(prefix)
    except OSError:  # another process wrote the same prefix first
        if not prefix.is_dir():
            raise
        _remove_tree(staging)
    return _PREFIXES.setdefault(given, prefix)


#: The prefix of each set of package folders as the workspace names them, in this process: a
#: launch's xacro commands each asked again, resolving every folder (10 expansions of the
#: course launch, 5-9 ms of its build); a prefix deleted since is written again.
_PREFIXES: dict[tuple, Path] = {}


def _remove_tree(folder: Path) -> None:
    import shutil

    shutil.rmtree(folder, ignore_errors=True)


@contextmanager
def environment_set(name: str, value: str):
    """Environment variable ``name`` set to ``value`` inside the block (then as it was)."""
    saved = os.environ.get(name)
    os.environ[name] = value
    try:
        yield
    finally:
        if saved is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = saved


def _explained(workspace: Workspace, path: Path, error: Exception) -> Exception:
    """The error to raise for ``error`` from xacro: the first of its chain (xacro wraps
    what it catches in ``XacroException.exc``) that says what is wrong, by type."""
    from xml.parsers.expat import ExpatError

    import xacro
    import xacro.substitution_args  # (xacro imports it only once a $(...) is evaluated)
    from ament_index_python.packages import PackageNotFoundError

    chain: BaseException | None = error
    seen: list[BaseException] = []
    while chain is not None and chain not in seen:
        seen.append(chain)
        if isinstance(chain, PackageNotFoundError):
            return _missing_package(workspace, path, chain)
        if isinstance(chain, xacro.substitution_args.ArgException):
            return WorkspaceError(f"{path}: $(arg {chain}) has no value; give it as {chain}:=VALUE")
        if isinstance(chain, ExpatError):
            return WorkspaceError(f"{path}: not well-formed XML: {chain}")
        chain = getattr(chain, "exc", None) or chain.__cause__ or chain.__context__
    if isinstance(error, (xacro.XacroException, OSError, ValueError, NameError, TypeError)):
        # One line: xacro's messages run on ("... is not defined \nwhen evaluating ...").
        return WorkspaceError(f"{path}: xacro error: {' '.join(str(error).split())}")
    return error


def _missing_package(workspace: Workspace, path: Path, error: BaseException) -> Exception:
    """MissingPackageError for ament's PackageNotFoundError: the package's name is the
    argument of the ament lookup that raised it (``get_package_prefix(package_name)``)."""
    tb = error.__traceback__
    name = None
    while tb is not None:
        name = tb.tb_frame.f_locals.get("package_name", name)
        tb = tb.tb_next
    if not isinstance(name, str):
        return WorkspaceError(f"{path}: xacro error: {error}")
    try:
        workspace.package(name, needed_by=path)
    except MissingPackageError as e:
        return e
    return WorkspaceError(f"{path}: xacro error: {error}")
