"""One exception hierarchy for every user-facing error of omtp_drake.

Every error names the bad value and, where there is a closed set of valid
choices, lists them, so the message alone tells the user what to type instead.
"""

from __future__ import annotations

import difflib
import math
import traceback
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any, Optional


class OmtpError(Exception):
    """Base class of every error raised on purpose by omtp_drake."""


class ConfigError(OmtpError, ValueError):
    """A configuration value (scenario field, system parameter) is invalid."""


class ScenarioError(OmtpError):
    """A scenario cannot be found or loaded (unknown name, missing file, bad YAML)."""


class UnknownNameError(OmtpError, KeyError):
    """A name (frame, pose, robot, camera, part...) is not one of the valid ones."""

    def __init__(self, kind: str, name: str, valid: Iterable[str], *, closest: bool = False):
        self.kind = kind
        self.name = name
        self.valid = sorted(valid)
        hint = f"valid: {_short_list(self.valid)}" if self.valid else "there are none"
        if closest:
            near = difflib.get_close_matches(str(name), self.valid, n=3, cutoff=0.4)
            if near:
                hint = f"closest: {', '.join(near)}; {hint}"
        super().__init__(f"unknown {kind} {name!r}; {hint}")

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self.args[0]


class StateError(OmtpError, RuntimeError):
    """A call made when its object cannot take it yet or any more: a recording not
    yet advanced, a constraint declared after ``Finalize``, an object still held
    (the message says what to do first)."""


class FrameError(OmtpError):
    """A transform cannot be looked up (e.g. a time outside the buffer's history)."""


class SimulationError(OmtpError):
    """The simulation cannot do what was asked (e.g. no free part left in the pool)."""


class PlanningError(SimulationError):
    """No motion does what was asked: a pose out of reach or outside the joint
    limits, a goal in collision, no collision-free path (the message says which)."""


class CollisionError(SimulationError):
    """A motion touched something it should not (the message names both bodies);
    the arm stopped there."""


class NotSupportedError(OmtpError, NotImplementedError):
    """A ROS name (function, class, method, argument) that ``omtp-drake ros-run`` does
    not provide; the message names it."""


class BenchmarkError(OmtpError):
    """A benchmark cannot measure what it was asked to: a measured run that did not
    succeed, or no ``bench/`` next to the package (it runs from a source checkout)."""


class WorkspaceError(ConfigError):
    """A student's own file (URDF, xacro, SDF, world, launch file) or workspace folder
    cannot be used; the message names the file (and line where known) and the value."""


class MissingPackageError(WorkspaceError):
    """A ROS package or Gazebo model that no workspace folder provides; the message
    names it, the file that needs it and the flag that supplies it."""

    def __init__(self, kind: str, name: str, needed_by: object, searched: str):
        self.kind = kind
        self.name = name
        self.needed_by = str(needed_by)
        super().__init__(
            f"{self.needed_by}: {kind} {name!r} not found; add the folder that holds it with "
            f"--workspace DIR (searched: {searched})"
        )


class BrowserError(OmtpError):
    """Headless chromium is missing, or did not render a replay in time."""


def _short_list(names: list[str], limit: int = 40) -> str:
    if len(names) <= limit:
        return ", ".join(names)
    return ", ".join(names[:limit]) + f", ... ({len(names) - limit} more)"


#: The fastest rate (Hz) a scenario may set for a periodic system: 10x the fastest
#: default (DiffIK and the arm commanders, 100 Hz). A faster one only makes a run
#: crawl (a camera at 1e9 Hz would take hours per simulated second).
MAX_RATE_HZ = 1000.0


def check_rate(what: str, value: float) -> None:
    """ConfigError unless ``0 < value <= MAX_RATE_HZ`` (NaN and inf are refused)."""
    if not 0 < value <= MAX_RATE_HZ:
        raise ConfigError(f"{what} must be in (0, {MAX_RATE_HZ:g}] Hz, got {value}")


def check_positive(what: str, value: Any) -> float:
    """``value`` as a finite number > 0, or ConfigError naming ``what``."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a number > 0, got {value!r}") from None
    if not (number > 0 and math.isfinite(number)):
        raise ConfigError(f"{what} must be a finite number > 0, got {value!r}")
    return number


def check_duration(what: str, value: Any, *, zero: bool = False) -> float:
    """``value`` (seconds, or anything with ``to_sec()``: a rospy Duration) as a finite time
    > 0 s (``>= 0`` with ``zero``), or ConfigError (a ValueError) naming ``what``: never inf
    or nan."""
    try:
        value = float(value.to_sec() if hasattr(value, "to_sec") else value)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a time in seconds, got {value!r}") from None
    if not ((value >= 0 if zero else value > 0) and math.isfinite(value)):
        raise ConfigError(f"{what} must be a finite time {'>=' if zero else '>'} 0 s, got {value!r}")
    return value


def check_vector(what: str, value: Iterable[float], *, max_norm: float = math.inf) -> list[float]:
    """``value`` as 3 finite numbers (of norm at most ``max_norm``), or ConfigError
    naming ``what`` and what it got."""
    try:
        v = [float(x) for x in value]
    except (TypeError, ValueError):
        v = []
    norm = math.sqrt(sum(x * x for x in v))
    if len(v) != 3 or not all(math.isfinite(x) for x in v) or norm > max_norm:
        limit = f" of at most {max_norm:g}" if math.isfinite(max_norm) else ""
        shown = list(value) if isinstance(value, Iterable) else value
        raise ConfigError(f"{what} needs 3 finite numbers{limit}, got {shown!r}")
    return v


class StartInCollisionError(PlanningError):
    """The arm's start configuration is in collision and no free one is near it
    (the message names the touching pairs)."""


class GoalInCollisionError(PlanningError):
    """The goal configuration, or every IK solution of a goal pose, is in collision
    (the message names the touching pairs)."""


class UnreachableError(PlanningError):
    """A goal the arm cannot take: a pose out of its reach, or a pose or joint values
    only outside its joint limits (the message says by how much, or which joint)."""


class MissingExtraError(OmtpError, ImportError):
    """An optional part of the project needs packages that are not installed; the
    message names the pyproject extra that installs them."""


# ----------------------------------------------------------------------------- exceptions told


def exception_place(e: BaseException, mine: Optional[Callable[[str], bool]] = None) -> str:
    """`` (at file.py:LINE in function)``: the deepest frame of ``e``'s traceback, or the
    deepest whose file ``mine`` accepts (``""`` when none is)."""
    frames = [f for f in traceback.extract_tb(e.__traceback__) if mine is None or mine(f.filename)]
    if not frames:
        return ""
    frame = frames[-1]
    return f" (at {Path(frame.filename).name}:{frame.lineno} in {frame.name})"


def describe_exception(
    e: BaseException,
    mine: Optional[Callable[[str], bool]] = None,
    *,
    place: Optional[str] = None,
    hint: str = "",
) -> str:
    """``Type: message (at file.py:LINE in function)`` on one line: the message cut at 500
    characters, then ``hint`` (what to do about it), then ``place`` (default: as
    :func:`exception_place` chooses it with ``mine``)."""
    text = " ".join(str(e).split())
    where = exception_place(e, mine) if place is None else place
    return f"{type(e).__name__}: {text[:500]}{hint}{where}"


def exception_frames(e: BaseException, mine: Callable[[str], bool]) -> list[str]:
    """``file.py:LINE in function: code`` of the frames of ``e``'s traceback whose file ``mine``
    accepts (a script's own, a workspace's), outermost first."""
    return [
        f"{Path(f.filename).name}:{f.lineno} in {f.name}: {(f.line or '').strip()}"
        for f in traceback.extract_tb(e.__traceback__)
        if mine(f.filename)
    ]


def exception_kind(e: BaseException) -> dict[str, Any]:
    """What ``e`` is, as data for whoever judges a run (never its message): ``type``, the
    names of its classes (``kinds``, most derived first) and its ``errno`` (None unless an
    OSError with one)."""
    return {
        "type": type(e).__name__,
        "kinds": [c.__name__ for c in type(e).__mro__ if c is not object],
        "errno": e.errno if isinstance(e, OSError) else None,
        "filename": str(e.filename) if isinstance(e, OSError) and e.filename is not None else None,
    }
