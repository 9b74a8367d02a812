"""tf as ROS broadcasts it: which of the cell's frames go on ``/tf_static`` and which on
``/tf``, at which pose and stamp (transport-neutral: the ROS 2 node and the bags send it).

The frames and their tree are the tf buffer's (:class:`~omtp_drake.cell.frames.FrameTree`,
:class:`~omtp_drake.sim.tf.TfBuffer`): one source of which frames exist. The rules are
robot_state_publisher's, for the links of the cell's URDF, and the course's logical
cameras', for what they see:

- a frame fixed to its parent (a fixed joint, a frame fixed in its body) is *static*: sent
  once, at the start, on ``/tf_static`` (reliable, transient local: a late listener gets it);
- a frame across a joint that moves (revolute, prismatic: what ``/joint_states`` names)
  goes on ``/tf`` at the joint state rate, stamped with the simulated time;
- a free body (a floating joint: the parts, a robot spawned without a weld) is no tf frame
  (robot_state_publisher skips floating joints); its ground truth is ``/gazebo/model_states``;
- each model a logical camera sees is ``<camera>_<model>_frame``, child of ``<camera>_frame``,
  at the pose of the camera's last image, stamped with the image's time.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame, JointIndex
from pydrake.systems.framework import Context

from omtp_drake.cell.frames import FrameTree
from omtp_drake.sim.tf import TfBuffer


@dataclass(frozen=True)
class TfEdge:
    """One transform of a tf message: ``X_PC``, the pose of ``child`` in ``parent`` at ``time``."""

    parent: str
    child: str
    time: float
    X_PC: RigidTransform


class TfBroadcast:
    """The tf edges of ``plant``, a station's, with ``tf`` its buffer (see the module doc)."""

    def __init__(self, plant: MultibodyPlant, tf: TfBuffer):
        self._tf = tf
        self._plant = plant
        tree = FrameTree(plant)
        floating = set()
        for j in range(plant.num_joints()):
            joint = plant.get_joint(JointIndex(j))
            if joint.num_velocities() == 6:
                floating.add(joint.child_body().body_frame().name())
        #: (parent, child, its frame index) of the edges fixed, and of those across a joint that moves.
        self._static: list[tuple[str, str, Frame]] = []
        self._moving: list[tuple[str, str, Frame]] = []
        for parent, child in tree.edges():
            if child in floating:
                continue
            entry = (parent, child, tree.frame(child))
            (self._static if tree.is_fixed(child) else self._moving).append(entry)
        self._frames = {parent: tree.frame(parent) for parent, _, _ in self._static + self._moving}

    @property
    def frame_names(self) -> list[str]:
        """The plant frames tf carries (static or moving), sorted."""
        return sorted({c for _, c, _ in self._static + self._moving} | set(self._frames))

    def static(self, root_context: Context) -> list[TfEdge]:
        """The static edges at ``root_context``'s time (for ``/tf_static``)."""
        return self._edges(self._static, root_context)

    def moving(self, root_context: Context) -> list[TfEdge]:
        """The edges across joints that move, at ``root_context``'s time (for ``/tf``)."""
        return self._edges(self._moving, root_context)

    def detected(self, time: Optional[float] = None) -> list[TfEdge]:
        """The frames of the models the logical cameras see at ``time`` (None: the buffer's
        latest) for ``/tf``, each at its image's pose and stamp."""
        tf = self._tf
        out = []
        for name, camera in sorted(tf.detected_frames(time).items()):
            stamp = tf.image(camera, time).time
            parent = f"{camera}_frame"
            out.append(TfEdge(parent, name, stamp, tf.lookup_transform(parent, name, stamp).transform))
        return out

    def _edges(self, edges: list[tuple[str, str, Frame]], root_context: Context) -> list[TfEdge]:
        plant_context = self._plant.GetMyContextFromRoot(root_context)
        t = root_context.get_time()
        return [
            TfEdge(parent, child, t, frame.CalcPose(plant_context, self._frames[parent]))
            for parent, child, frame in edges
        ]
