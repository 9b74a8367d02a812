"""The environment a course script or a launch's node runs in: the ROS-named packages of
``omtp_drake/ros/shims`` (``rospy``, ``moveit_commander``, ``tf2_ros``...) first on
``sys.path``, its own ``sys.argv``, and the ROS module names taken off again afterwards (so
a real ROS installation is never shadowed outside the run)."""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path

#: The folder of the ROS-named packages (put first on sys.path during a run only).
SHIM_DIR = Path(__file__).resolve().parents[1] / "shims"
#: The top-level names it provides.
SHIM_PACKAGES = tuple(sorted(p.name for p in SHIM_DIR.iterdir() if (p / "__init__.py").is_file()))


@contextlib.contextmanager
def script_environment(script: Path, args: Sequence[str]) -> Iterator[None]:
    """sys.argv, sys.path (the shims, then the script's folder) and sys.modules set
    for ``script``; all three restored afterwards."""
    saved_argv, saved_path = sys.argv[:], sys.path[:]
    hidden = {n: m for n, m in sys.modules.items() if n.split(".")[0] in SHIM_PACKAGES}
    for name in hidden:
        del sys.modules[name]  # e.g. a real rospy imported before: the script gets ours
    before = set(sys.modules)
    sys.argv = [str(script), *args]
    sys.path[:0] = [str(SHIM_DIR), str(script.parent)]
    try:
        yield
    finally:
        sys.argv, sys.path[:] = saved_argv, saved_path
        folder = str(script.parent) + os.sep
        for name in set(sys.modules) - before:
            top = name.split(".")[0]
            origin = str(getattr(sys.modules[name], "__file__", "") or "")
            # The ROS names, and the script's own modules (not the project's, wherever it is).
            if top in SHIM_PACKAGES or (top != "omtp_drake" and origin.startswith(folder)):
                del sys.modules[name]
        sys.modules.update(hidden)
