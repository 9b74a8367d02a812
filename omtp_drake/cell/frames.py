"""Frames by name, like ROS tf: every frame of the factory and the transforms between them.

Names are the reference frame-tree names (``robot1_base_link``,
``vacuum_gripper2_suction_cup``, ``bin_1_drop_point``, ``logical_camera_1_frame``...),
unique across the whole plant, plus ``world``.

:class:`FrameTree` holds the plant's named frames and their parent -> child tree;
``lookup_transform(plant_context, target, source)`` evaluates a plant Context and
returns ``X_TS``, the pose of the source frame in the target frame (tf2's meaning).
tf2's buffer with history over a running station is
:class:`omtp_drake.sim.tf.TfBuffer`; the picture of the tree is
:func:`omtp_drake.viz.tree.view_frames`.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Optional

from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame, FrameIndex, JointIndex
from pydrake.systems.framework import Context

from omtp_drake.errors import ConfigError, UnknownNameError

if TYPE_CHECKING:
    pass

_log = logging.getLogger(__name__)

#: Times closer than this [s] are the same time (snapshots, range checks).
TIME_EPS = 1e-9


class FrameTree:
    """The named frames of a plant and their parent -> child tree.

    Joint-internal frames (``*_joint_parent``), model-instance frames
    (``__model__``) and the frames Drake adds itself when it finalizes the plant
    (ephemeral, e.g. ``world_welds_to_robot1_base_link_world_F``) are not listed;
    everything else is, by its own name; a name two models' frames share (a world's
    models each with a ``link``) is Gazebo's scoped name, ``MODEL::link``.
    """

    def __init__(self, plant: MultibodyPlant):
        if not plant.is_finalized():
            raise ConfigError("FrameTree needs a finalized plant")
        self._plant = plant
        hidden: set[int] = set()
        #: body index -> name of the body frame on the parent side of its joint
        self._inboard: dict[int, str] = {}
        #: body index -> whether its inboard joint moves (has positions)
        self._moving: dict[int, bool] = {}
        for j in range(plant.num_joints()):
            joint = plant.get_joint(JointIndex(j))
            for f in (joint.frame_on_parent(), joint.frame_on_child()):
                if not f.is_body_frame():
                    hidden.add(int(f.index()))
            child = int(joint.child_body().index())
            self._inboard[child] = joint.parent_body().body_frame().name()
            self._moving[child] = joint.num_positions() > 0
        listed = []
        for i in range(plant.num_frames()):
            frame = plant.get_frame(FrameIndex(i))
            if i not in hidden and not frame.name().endswith("__model__") and not frame.is_ephemeral():
                listed.append(frame)
        counts: dict[str, int] = {}
        for frame in listed:
            counts[frame.name()] = counts.get(frame.name(), 0) + 1
        frames: dict[str, Frame] = {}
        duplicates: set[str] = set()
        for frame in listed:
            name = frame.name()
            if counts[name] > 1:  # Gazebo's scoped name: two models' links both called "link"
                name = f"{plant.GetModelInstanceName(frame.model_instance())}::{name}"
            if name in frames:
                duplicates.add(name)
            frames[name] = frame
        if duplicates:
            raise ConfigError(f"frame names must be unique; repeated: {', '.join(sorted(duplicates))}")
        self._frames = frames

    @property
    def plant(self) -> MultibodyPlant:
        return self._plant

    def names(self) -> list[str]:
        """Every frame name, sorted."""
        return sorted(self._frames)

    def __contains__(self, name: str) -> bool:
        return name in self._frames

    def frame(self, name: str) -> Frame:
        """The plant frame called ``name`` (the error lists the closest names)."""
        try:
            return self._frames[name]
        except KeyError:
            raise UnknownNameError("frame", name, self._frames, closest=True) from None

    def parent(self, name: str) -> Optional[str]:
        """The frame ``name`` hangs from in the tree (None for ``world``).

        A body frame hangs from the body frame on the other side of its inboard
        joint (``world`` for a free body); any other frame from its body's frame.
        """
        frame = self.frame(name)
        body = frame.body()
        if not frame.is_body_frame():
            return body.body_frame().name()
        if body.index() == self._plant.world_body().index():
            return None
        return self._inboard.get(int(body.index()), "world")

    def is_fixed(self, name: str) -> bool:
        """Whether ``name`` is fixed to its parent (False across a moving or free joint)."""
        frame = self.frame(name)
        if not frame.is_body_frame() or frame.body().index() == self._plant.world_body().index():
            return True
        return not self._moving.get(int(frame.body().index()), True)

    def edges(self) -> list[tuple[str, str]]:
        """(parent, child) pairs of the whole tree."""
        return [(p, n) for n in self.names() if (p := self.parent(n)) is not None]

    def lookup_transform(self, plant_context: Context, target: str, source: str) -> RigidTransform:
        """``X_TS``: the pose of ``source`` in ``target`` (tf2's lookup_transform)."""
        return self.frame(source).CalcPose(plant_context, self.frame(target))


# ----------------------------------------------------------------------------
# Stamped values (tf2's geometry_msgs)


# ----------------------------------------------------------------------------
# The buffer


# ----------------------------------------------------------------------------
# view_frames
