"""The packages the course's files need and no student has: the project's stand-ins.

The course's launch files and xacro say ``$(find ur_description)`` (ROS Melodic's UR
macros ``ur5_robot`` / ``ur10_robot``), ``$(find gazebo_ros)/launch/empty_world.launch``,
``$(find omtp_moveit_config)/launch/move_group.launch`` and ``$(find xacro)/xacro``.
The project writes its own stand-ins of these in ``standins/`` (their numbers are
example-robot-data's, its meshes are theirs). :func:`standin_dirs` gives the folder to
pass to :meth:`Workspace.from_dirs` as ``bundled``, so a student's own package of the
same name is found first.

The stand-in ``ur_description`` refers to its meshes as ``package://ur_description/
meshes/...``; those are example-robot-data's, so the stand-ins are laid out once in
the model cache with ``ur_description/meshes`` pointing at the installed meshes
(nothing is downloaded).
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
from pathlib import Path

#: The stand-ins' sources, shipped with the package.
STANDINS_DIR = Path(__file__).resolve().parent / "standins"


@functools.cache
def standin_dirs() -> tuple[Path, ...]:
    """The folder of the stand-in packages (laid out in the model cache on first use)."""
    from omtp_drake.assets import cache_entry
    from omtp_drake.ur_arms import ur_description_dir

    digest = hashlib.sha1()
    sources = sorted(p for p in STANDINS_DIR.rglob("*") if p.is_file())
    for path in sources:
        digest.update(str(path.relative_to(STANDINS_DIR)).encode() + path.read_bytes())
    out = cache_entry(f"standins-{digest.hexdigest()[:10]}")
    if not out.is_dir():
        tmp = out.with_name(out.name + f".{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(STANDINS_DIR, tmp)
        (tmp / "ur_description" / "meshes").symlink_to(ur_description_dir() / "meshes")
        try:
            tmp.rename(out)
        except OSError:  # another process laid it out first
            shutil.rmtree(tmp, ignore_errors=True)
    return (out,)
