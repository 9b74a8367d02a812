"""What the pick-and-place controller is doing and has done: plain values shared by
the state machine (:mod:`~omtp_drake.control.pick_and_place.machine`) and its
system (:mod:`~omtp_drake.control.pick_and_place.system`), and read by the tasks.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum, StrEnum
from typing import Any, Optional

from pydrake.math import RigidTransform

from omtp_drake.control.tool_paths import Path


class Mode(Enum):
    """What the controller is doing."""

    INIT = "INIT"
    WAIT_PART = "WAIT_PART"
    APPROACH = "APPROACH"
    DESCEND = "DESCEND"
    ATTACH = "ATTACH"
    TRANSFER = "TRANSFER"
    RELEASE = "RELEASE"
    HOME = "HOME"
    #: The bin holds no more parts the arm can reach: the arm went Home and the
    #: controller stopped (the task cannot finish).
    BIN_FULL = "BIN_FULL"


class PickFailure(StrEnum):
    """Why a pick attempt failed (its value is the JSON output's ``failure_reason``)."""

    #: Suction did not attach in time.
    ATTACH_TIMEOUT = "attach_timeout"
    #: The part fell off the cup in transit.
    DROPPED = "dropped"
    #: It fell off in transit and came to rest in the bin (there, but not by a place).
    DROPPED_INTO_BIN = "dropped_into_bin"
    #: No part was seen to pick.
    NO_PART = "no_part"
    #: DiffIK could not follow the path.
    TRACKING = "tracking"
    #: The part was not in the bin after its release.
    MISSED_BIN = "missed_bin"
    #: The part is out of reach or was not seen again.
    LOST = "lost"
    #: The bin holds no more parts the arm can reach.
    BIN_FULL = "bin_full"


@dataclass(frozen=True)
class PickRecord:
    """One pick attempt, as it ended."""

    part: str
    start: float
    end: float
    success: bool
    #: Why it failed (None for a success).
    reason: Optional[PickFailure] = None
    attempt: int = 1
    #: Where the part was when the attempt ended, for a part given up on.
    position: Optional[tuple[float, float, float]] = None
    #: The controller will not try this part again (``lost``, ``dropped_into_bin``,
    #: or its last attempt failed): it lies where ``position`` says.
    given_up: bool = False

    @property
    def cycle_time(self) -> float:
        return self.end - self.start

    def to_dict(self) -> dict:
        return {
            "part": self.part,
            "start": self.start,
            "end": self.end,
            "success": self.success,
            "failure_reason": "" if self.reason is None else self.reason.value,
            "attempt": self.attempt,
            "cycle_time": self.cycle_time,
            "position": list(self.position) if self.position is not None else None,
            "given_up": self.given_up,
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> PickRecord:
        """The record of :meth:`to_dict`."""
        position = data.get("position")
        return cls(
            part=data["part"],
            start=data["start"],
            end=data["end"],
            success=data["success"],
            reason=PickFailure(data["failure_reason"]) if data["failure_reason"] else None,
            attempt=data["attempt"],
            position=tuple(position) if position is not None else None,
            given_up=data.get("given_up", False),
        )


@dataclass(frozen=True)
class ControlState:
    """What the controller is doing now (its control state)."""

    mode: Mode = Mode.INIT
    mode_start: float = 0.0
    path: Path = Path()
    suction: bool = False
    #: The part being picked and where the camera saw it.
    part: str = ""
    X_WP: Optional[RigidTransform] = None
    pick_start: float = 0.0
    attempt: int = 1
    #: Parts placed so far (the next slot) and parts given up on.
    placed: int = 0
    ignored: tuple[str, ...] = ()
    bad_tracking_since: float = math.nan
    last_seen: float = 0.0
    #: Ask DiffIK to restart from the measured joints (one controller period).
    reset_ik: bool = False
    #: Since when the part being retried has not been seen by any camera.
    missing_since: float = math.nan
    #: The part to pick next as last seen, where and in which image; at rest when
    #: the image before agreed (to pick only parts at rest).
    candidate: str = ""
    candidate_X: Optional[RigidTransform] = None
    candidate_time: float = math.nan
    candidate_at_rest: bool = False
    #: A part dropped in transit whose record waits until a camera sees where it
    #: came to rest (the record then says where it landed).
    pending_drop: Optional[PickRecord] = None

    def pose_at(self, t: float) -> Optional[RigidTransform]:
        """The tool's desired pose ``X_WE`` at ``t`` (None without a path)."""
        return self.path.pose_at(t)

    def __deepcopy__(self, memo: dict) -> ControlState:
        return self  # immutable: Drake clones abstract state at every update


@dataclass(frozen=True)
class PickHistory:
    """What the controller has done (reported apart from its control state)."""

    picks: tuple[PickRecord, ...] = ()
    #: Largest tool tracking error seen (m).
    worst_tracking_error: float = 0.0

    def __deepcopy__(self, memo: dict) -> PickHistory:
        return self  # immutable: Drake clones abstract state at every update

    def with_step(self, record: Optional[PickRecord], tracking_error: float) -> PickHistory:
        """This history after one update: ``record`` (if any) appended, the worst
        tracking error raised to ``tracking_error`` (itself when nothing changed)."""
        if record is None and tracking_error <= self.worst_tracking_error:
            return self
        return PickHistory(
            self.picks + ((record,) if record else ()), max(self.worst_tracking_error, tracking_error)
        )


def position_of(X_WP: Optional[RigidTransform]) -> Optional[tuple[float, float, float]]:
    """(x, y, z) of ``X_WP`` for a record (None if unknown)."""
    if X_WP is None:
        return None
    x, y, z = (float(v) for v in X_WP.translation())
    return (x, y, z)
