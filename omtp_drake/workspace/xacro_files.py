"""xacro expanded with ``$(find PKG)`` resolved in a :class:`~omtp_drake.workspace.Workspace`.

The PyPI ``xacro`` resolves ``$(find PKG)`` through ``ament_index_python`` (not on
PyPI, and ROS 2's index, not a catkin workspace's). Here the lookup goes to the
workspace's packages instead, for the expansion only: xacro's own substitution
hook is pointed at the workspace while one expansion runs (one at a time, under a
lock) and restored after.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path

from omtp_drake.errors import MissingPackageError, WorkspaceError
from omtp_drake.workspace.packages import Workspace

#: xacro's $(find) is module state: one expansion at a time (re-entrant: a launch.py that runs
#: xacro itself may expand another file inside, omtp_drake.ros2.launch_py).
_XACRO_LOCK = threading.RLock()


def expand_xacro_in(
    workspace: Workspace, path: str | os.PathLike, args: Mapping[str, str] | None = None
) -> str:
    """The URDF text of the xacro (or plain URDF) file ``path`` with ``args``, its
    ``$(find PKG)`` resolved in ``workspace``.

    Raises MissingPackageError for a package the workspace does not have, and
    WorkspaceError naming the file for any other xacro error (a missing
    ``$(arg)``, a bad include, malformed XML).
    """
    import xacro

    path = Path(path)
    if not path.is_file():
        raise WorkspaceError(f"{path}: no such file")
    with _XACRO_LOCK, _find_in(workspace, path):
        try:
            doc = xacro.process_file(str(path), mappings=dict(args or {}))
        except Exception as e:
            raise _explained(path, e) from None
    return doc.toprettyxml(indent="  ")


def _explained(path: Path, error: Exception) -> Exception:
    """The error to raise for ``error`` from xacro: the first of its chain (xacro wraps
    what it catches in ``XacroException.exc``) that says what is wrong, by type."""
    from xml.parsers.expat import ExpatError

    import xacro

    chain: BaseException | None = error
    seen: list[BaseException] = []
    while chain is not None and chain not in seen:
        seen.append(chain)
        if isinstance(chain, MissingPackageError):
            return chain
        if isinstance(chain, xacro.substitution_args.ArgException):
            return WorkspaceError(f"{path}: $(arg {chain}) has no value; give it as {chain}:=VALUE")
        if isinstance(chain, ExpatError):
            return WorkspaceError(f"{path}: not well-formed XML: {chain}")
        chain = getattr(chain, "exc", None) or chain.__cause__ or chain.__context__
    if isinstance(error, (xacro.XacroException, OSError, ValueError, NameError, TypeError)):
        return WorkspaceError(f"{path}: xacro error: {error}")
    return error


@contextmanager
def xacro_finds_in(workspace: Workspace, needed_by: str | os.PathLike) -> Iterator[None]:
    """While the block runs, xacro (called by anyone, e.g. a launch.py) resolves ``$(find PKG)``
    in ``workspace``."""
    with _XACRO_LOCK, _find_in(workspace, Path(needed_by)):
        yield


@contextmanager
def _find_in(workspace: Workspace, needed_by: Path):
    from xacro import substitution_args

    def find(package: str) -> str:
        return str(workspace.package(package, needed_by=needed_by))

    saved = substitution_args._eval_find, substitution_args._eval_dict["find"]
    substitution_args._eval_find = find
    substitution_args._eval_dict["find"] = find
    try:
        yield
    finally:
        substitution_args._eval_find, substitution_args._eval_dict["find"] = saved
