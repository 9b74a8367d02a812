"""How the motion planner names configurations, poses and touching bodies in its
messages (errors and log lines)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from pydrake.math import RigidTransform


def fmt_q(q: Sequence[float] | np.ndarray) -> str:
    """Joint positions as ``[a, b, ...]`` (3 decimals)."""
    return "[" + ", ".join(f"{v:.3f}" for v in q) + "]"


def fmt_pose(X: RigidTransform) -> str:
    """A pose by its position, ``p=(x, y, z)`` (m, 3 decimals)."""
    p = X.translation()
    return f"p=({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f})"


def fmt_pairs(pairs: list[tuple[str, str]]) -> str:
    """Touching (robot, other) pairs as ``a / b, c / d``."""
    return ", ".join(f"{a} / {b}" for a, b in pairs)
