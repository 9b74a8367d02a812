"""The plant's named frames in the tf buffer's snapshots, and their poses at a time.

:class:`PlantFramePoses` knows each named frame of the plant (its body, its pose
in that body, its parent in the tree) and gives ``X_WF`` in one snapshot, or at
a time between two snapshots with each parent -> child transform on the path
interpolated as tf2 does (linear in translation, slerp in rotation). Detected
frames (the cameras') are the :class:`~omtp_drake.sim.tf.TfBuffer`'s: it passes
a function that gives their camera and pose in the camera.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Optional

from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform

from omtp_drake.cell.frames import FrameTree
from omtp_drake.cell.poses import interpolate_pose

#: (name, time) -> (camera, X_CM) of a detected frame.
Detection = Callable[[str, float], tuple[str, RigidTransform]]


@dataclass(frozen=True)
class Snapshot:
    time: float
    #: The plant's body poses output at ``time``, copied (``Clone`` of its value): one
    #: C++ copy, where a tuple of RigidTransform is a Python object per body; most
    #: snapshots are never read.
    poses: AbstractValue

    @functools.cached_property
    def X_WB(self) -> tuple[RigidTransform, ...]:
        """X_WB of every body, by body index (made at the first read)."""
        return tuple(self.poses.get_value())


class PlantFramePoses:
    """The plant's named frames (see :class:`FrameTree`) and their world poses in snapshots."""

    def __init__(self, tree: FrameTree):
        #: static frame name -> (body index, X_BF)
        self.static: dict[str, tuple[int, RigidTransform]] = {}
        for name in tree.names():
            frame = tree.frame(name)
            self.static[name] = (int(frame.body().index()), frame.GetFixedPoseInBodyFrame())
        self.parents: dict[str, Optional[str]] = {n: tree.parent(n) for n in self.static}
        self._body_frames = {n for n in self.static if tree.frame(n).is_body_frame()}

    def in_snapshot(self, snapshot: Snapshot, name: str) -> RigidTransform:
        """X_WF of a plant frame in one snapshot."""
        body, X_BF = self.static[name]
        return snapshot.X_WB[body] @ X_BF

    def world_pose(
        self,
        name: str,
        before: Snapshot,
        after: Optional[Snapshot],
        time: float,
        cache: dict[str, RigidTransform],
        detection: Detection,
    ) -> RigidTransform:
        """X_WF at ``time``: from ``before`` alone, or each edge interpolated."""
        if name in cache:
            return cache[name]
        if name in self.static:
            parent = self.parents[name]
            if after is None:
                X = self.in_snapshot(before, name)
            elif parent is None:
                X = RigidTransform()
            else:
                if name in self._body_frames:
                    alpha = (time - before.time) / (after.time - before.time)
                    X_PF = interpolate_pose(
                        self.in_snapshot(before, parent).InvertAndCompose(self.in_snapshot(before, name)),
                        self.in_snapshot(after, parent).InvertAndCompose(self.in_snapshot(after, name)),
                        alpha,
                    )
                else:
                    X_PF = self.static[name][1]  # fixed in its body: X_BF
                X = self.world_pose(parent, before, after, time, cache, detection) @ X_PF
        else:
            camera, X_CM = detection(name, time)
            X = self.world_pose(f"{camera}_frame", before, after, time, cache, detection) @ X_CM
        cache[name] = X
        return X
