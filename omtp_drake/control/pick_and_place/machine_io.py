"""What the pick-and-place state machine reads and decides, in plain values.

:class:`MachineInput` is one update's view (the time, the cameras' images, the
gripper's state, the measured tool pose and joint positions); :class:`Decision` is
what :class:`~omtp_drake.control.pick_and_place.machine.PickMachine` answers (the
next control state and the record of an attempt that ended).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

from pydrake.math import RigidTransform

from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.cell.suction import GripperState
from omtp_drake.control.pick_and_place.controller_state import ControlState, Mode, PickRecord
from omtp_drake.control.tool_paths import Path

#: The image of a camera that has taken none (time NaN, nothing in view).
NO_IMAGE = LogicalCameraImage(math.nan, "", RigidTransform(), ())


def _no_image() -> LogicalCameraImage:
    return NO_IMAGE


@dataclass(frozen=True)
class MachineInput:
    """What one update sees.

    The camera images are read when the machine first asks for one (most modes
    never look: a moving arm follows its path), through the ``read_*`` functions,
    once per update; :meth:`seeing` makes an input of images in hand.

    Attributes:
        t: the time (s).
        X_WE: the tool's pose at the measured joint positions.
        gripper: the gripper's state (``attached``, the held ``part``).
        q: the arm's measured joint positions (rad), pan ... wrist 3.
        pick_image: the pick camera's latest image.
        bin_image: the bin camera's latest image (:data:`NO_IMAGE` without one).
        search_images: the other cameras' latest images.
        X_WE_desired: the control state's path at ``t``, when the caller has it at
            hand (the controller's pose table); None: the machine
            evaluates the path itself.
    """

    t: float
    X_WE: RigidTransform
    gripper: GripperState
    q: tuple[float, ...]
    read_pick_image: Callable[[], LogicalCameraImage] = field(default=_no_image, repr=False)
    read_bin_image: Callable[[], LogicalCameraImage] = field(default=_no_image, repr=False)
    read_search_images: Callable[[], tuple[LogicalCameraImage, ...]] = field(default=tuple, repr=False)
    X_WE_desired: Optional[RigidTransform] = None

    @classmethod
    def seeing(
        cls,
        t: float,
        X_WE: RigidTransform,
        gripper: GripperState,
        q: tuple[float, ...],
        pick_image: LogicalCameraImage = NO_IMAGE,
        bin_image: LogicalCameraImage = NO_IMAGE,
        search_images: tuple[LogicalCameraImage, ...] = (),
    ) -> MachineInput:
        """An input with these images."""
        return cls(t, X_WE, gripper, q, lambda: pick_image, lambda: bin_image, lambda: search_images)

    @cached_property
    def pick_image(self) -> LogicalCameraImage:
        return self.read_pick_image()

    @cached_property
    def bin_image(self) -> LogicalCameraImage:
        return self.read_bin_image()

    @cached_property
    def search_images(self) -> tuple[LogicalCameraImage, ...]:
        return self.read_search_images()


@dataclass(frozen=True)
class Decision:
    """What one update decides: the next control state (mode, tool path, suction),
    the record of an attempt that ended (None: none did) and the tool's tracking
    error (m) seen."""

    control: ControlState
    record: Optional[PickRecord] = None
    tracking_error: float = 0.0

    @property
    def mode(self) -> Mode:
        return self.control.mode

    @property
    def path(self) -> Path:
        """The tool path to follow (``X_WE`` by time)."""
        return self.control.path

    @property
    def vacuum(self) -> bool:
        """Suction on?"""
        return self.control.suction
