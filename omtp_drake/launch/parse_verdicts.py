"""Drake's parser's verdict on a world's model folders, kept in the model cache.

:func:`omtp_drake.launch.sdf_world.with_drake` asks Drake's parser whether it reads a
world's included model folders as they are (else each model is checked on its own, for
Gazebo's warnings). The parse is about half of what reading a course-layout world costs a
command's first build (libsdformat's session, ``bench/bench_launch.py --cold``) and its
answer only changes with the files: an accepted set of folders is remembered by the content
of every file under them, the workspace's packages and Drake's version; a refusal is not
kept (it is explained afresh each time). A file a model names in another package is not in
the key (its package's folder is): Drake's parse of the cell reads it again at the build.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
from pathlib import Path

from omtp_drake.assets import cache_entry, file_hash, write_atomic
from omtp_drake.workspace import Workspace


def known_accepted(model_dirs: list[Path], workspace: Workspace) -> bool:
    """Whether Drake's parser accepted these folders, as they are now, before."""
    entry = _entry(model_dirs, workspace)
    return entry is not None and entry.is_file()


def remember_accepted(model_dirs: list[Path], workspace: Workspace) -> None:
    """Keeps that Drake's parser accepts these folders as they are now."""
    entry = _entry(model_dirs, workspace)
    if entry is not None:
        write_atomic(entry, b"accepted\n")


def _entry(model_dirs: list[Path], workspace: Workspace) -> Path | None:
    """The cache entry of the folders' verdict (None: a file could not be read)."""
    key: list[object] = [_drake_version()]
    named = {**workspace.models, **workspace.packages}
    key.append(sorted((name, str(folder)) for name, folder in named.items()))
    for folder in model_dirs:
        files = sorted(str(p) for p in Path(folder).rglob("*") if p.is_file())
        hashes = [(f, file_hash(f)) for f in files]
        if any(h is None for _, h in hashes):
            return None
        key.append((str(folder), hashes))
    digest = hashlib.sha1(repr(key).encode()).hexdigest()[:24]
    return cache_entry(f"drake-verdicts/{digest}")


@functools.cache
def _drake_version() -> str:
    """The installed drake's version (a metadata lookup is 1-5 ms; the loaded pydrake is this
    process's for its whole life)."""
    return importlib.metadata.version("drake")
