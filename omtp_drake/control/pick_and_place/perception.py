"""What the pick-and-place controller sees: parts and the bin in logical-camera
images (plain values), never ground truth.

A part's pose is the image's ``X_WC`` times the reported ``X_CM``. Frames: W world,
C a camera, P a part's origin (its centre), Bin the bin's origin.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator, Sequence
from typing import Optional

import numpy as np
from pydrake.math import RigidTransform

from omtp_drake.cell import arms
from omtp_drake.cell.logical_camera import LogicalCameraImage
from omtp_drake.scenario import BinConfig, RobotConfig, TaskConfig

#: One part seen: its name, ``X_WP`` and the time of the image that showed it.
Sighting = tuple[str, RigidTransform, float]


class Perception:
    """Parts and the bin as the task's cameras show them to ``robot``.

    Args:
        config: the task (part type, image timeout, approach height...).
        robot: the picking arm.
        bin: the bin parts go into.
        part_size: a part's edge (m) by name.
    """

    def __init__(
        self, config: TaskConfig, robot: RobotConfig, bin: BinConfig, part_size: Callable[[str], float]
    ) -> None:
        self._config = config
        self._robot = robot
        self._bin = bin
        self.part_size = part_size
        self._p_WB = arms.base_pose(robot).translation()

    def fresh(self, image: LogicalCameraImage, t: float) -> bool:
        """Was ``image`` taken at most ``image_timeout`` s before ``t``?"""
        return image.time <= t and t - image.time <= self._config.image_timeout

    def parts_seen(
        self,
        t: float,
        pick: LogicalCameraImage,
        others: Callable[[], Sequence[LogicalCameraImage]],
        bin_image: Callable[[], LogicalCameraImage],
        ignored: Sequence[str],
    ) -> Optional[Iterator[Sighting]]:
        """The parts to pick (not ``ignored``): those in the pick camera's image, then
        those the ``others`` (the bin camera's and the search cameras' images) see
        outside the bin (a part that missed it or fell on the way); None if the pick
        camera's image is stale. The other images and the bin camera's (for where the
        bin is) are read only once the pick camera's sightings are used up: a camera
        computes its image when it is read, and most callers stop at the first
        sighting that suits them."""
        if not self.fresh(pick, t):
            return None
        part_type = self._config.part_type
        in_pick = [
            (m.name, pick.X_WC @ m.X_CM, pick.time)
            for m in pick.models
            if m.type == part_type and m.name and m.name not in ignored
        ]
        seen = {*ignored, *(name for name, _, _ in in_pick)}
        return itertools.chain(in_pick, self._outside_the_bin(t, others, bin_image, seen))

    def _outside_the_bin(
        self,
        t: float,
        images: Callable[[], Sequence[LogicalCameraImage]],
        bin_image: Callable[[], LogicalCameraImage],
        seen: set[str],
    ) -> Iterator[Sighting]:
        """The parts of the fresh ``images`` outside the bin but those ``seen`` (one sighting
        each), the images read at the first sighting asked for."""
        images_now = images()
        X_WBin = self.bin_pose(bin_image())
        for image in images_now:
            if not self.fresh(image, t):
                continue
            for m in image.models:
                if m.type != self._config.part_type or not m.name or m.name in seen:
                    continue
                X_WP = image.X_WC @ m.X_CM
                if not self._bin.contains(X_WP.translation(), X_WBin):
                    seen.add(m.name)
                    yield m.name, X_WP, image.time

    def reachable(self, X_WP: RigidTransform, size: float) -> bool:
        """Can the tool reach the part's top face, tool down, and the approach above it?"""
        p = X_WP.translation()
        radius = float(np.linalg.norm(p[:2] - self._p_WB[:2]))
        top = p[2] + size / 2
        return all(
            radius <= arms.tool_down_reach(self._robot, z) for z in (top, top + self._config.approach_height)
        )

    def bin_seen(self, image: LogicalCameraImage) -> Optional[RigidTransform]:
        """``X_WBin`` where the bin camera's image shows the bin (None: not in it)."""
        for m in image.models:
            if m.name == self._bin.name:
                return image.X_WC @ m.X_CM
        return None

    def bin_pose(self, bin_image: LogicalCameraImage) -> RigidTransform:
        """Where the bin is: as the bin camera last saw it, else the scenario's pose."""
        if math.isfinite(bin_image.time):
            seen = self.bin_seen(bin_image)
            if seen is not None:
                return seen
        return self._bin.X_WB()

    def seen_in_bin(self, t: float, bin_image: LogicalCameraImage, name: str) -> Optional[RigidTransform]:
        """``X_WP`` of part ``name`` if the bin camera's fresh image shows it in the bin."""
        if not self.fresh(bin_image, t):
            return None
        return self.pose_in_bin(bin_image, name)

    def pose_in_bin(self, image: LogicalCameraImage, name: str) -> Optional[RigidTransform]:
        """``X_WP`` of part ``name`` if ``image`` (the bin camera's) shows it inside
        the bin, where that image shows the bin."""
        X_WBin = self.bin_seen(image)
        for m in image.models:
            if m.name == name and X_WBin is not None:
                X_WP = image.X_WC @ m.X_CM
                return X_WP if self._bin.contains(X_WP.translation(), X_WBin) else None
        return None

    def in_bin(self, bin_image: LogicalCameraImage, name: str, released_at: float) -> Optional[bool]:
        """Does the bin camera see ``name`` inside the bin? None without a bin
        camera or before its first image taken ``settle_time`` after the release."""
        if (
            not math.isfinite(bin_image.time)
            or bin_image.time < released_at + self._config.settle_time - 1e-9
        ):
            return None
        return self.pose_in_bin(bin_image, name) is not None
