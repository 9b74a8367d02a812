"""Frames by name, like ROS tf: every frame of the factory and the transforms between them.

Names are the reference frame-tree names (``robot1_base_link``,
``vacuum_gripper2_suction_cup``, ``bin_1_drop_point``, ``logical_camera_1_frame``...),
unique across the whole plant, plus ``world``.

Two levels, as in ROS:

* :class:`FrameTree`: the plant's named frames and their parent -> child tree;
  ``lookup_transform(plant_context, target, source)`` evaluates a plant Context.
* :class:`TfBuffer`: tf2's buffer over a running station. ``record(context)``
  stores a snapshot (every frame's world pose and every logical camera's last
  image); lookups by name and time, interpolated between snapshots. Besides the
  plant's frames it knows one frame per model a logical camera sees,
  ``<camera>_<model>_frame`` (e.g. ``logical_camera_2_object_1_frame``), child of
  ``<camera>_frame``, at the pose the camera reported.

``lookup_transform(target, source)`` has tf2's meaning: it returns ``X_TS``, the
pose of the source frame in the target frame, i.e. the transform that takes data
expressed in ``source`` into ``target``.

Typical use::

    runtime = FactoryRuntime("lecture6_assignment3")
    buffer = TfBuffer(runtime.station)
    runtime.on_tick(lambda rt: buffer.record(rt.context))  # record every tick
    runtime.advance_to(1.5)
    X = buffer.lookup_transform("vacuum_gripper2_suction_cup",
                                "logical_camera_2_object_1_frame").transform
    view_frames(buffer, "frames")  # frames.pdf, frames.png
"""

from __future__ import annotations

import bisect
import logging
import math
import textwrap
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Frame, FrameIndex, JointIndex
from pydrake.systems.framework import Context, EventStatus

from omtp_drake.errors import ConfigError, FrameError, UnknownNameError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.text import Text

    from omtp_drake.logical_camera import LogicalCameraImage
    from omtp_drake.station import Station

_log = logging.getLogger(__name__)

#: Times closer than this [s] are the same time (snapshots, range checks).
TIME_EPS = 1e-9


class FrameTree:
    """The named frames of a plant and their parent -> child tree.

    Joint-internal frames (``*_joint_parent``), model-instance frames
    (``__model__``) and the frames Drake adds itself when it finalizes the plant
    (ephemeral, e.g. ``world_welds_to_robot1_base_link_world_F``) are not listed;
    everything else is, by its own name.
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
        frames: dict[str, Frame] = {}
        duplicates: set[str] = set()
        for i in range(plant.num_frames()):
            frame = plant.get_frame(FrameIndex(i))
            name = frame.name()
            if i in hidden or name == "__model__" or name.endswith("__model__") or frame.is_ephemeral():
                continue
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


@dataclass(frozen=True)
class TransformStamped:
    """tf2's ``TransformStamped``: the pose of ``child_frame_id`` in ``header_frame_id``.

    Attributes:
        header_frame_id: the target frame T.
        child_frame_id: the source frame S.
        time: the time of the transform [s] (simulated time).
        transform: ``X_TS``.
    """

    header_frame_id: str
    child_frame_id: str
    time: float
    transform: RigidTransform


@dataclass(frozen=True)
class PoseStamped:
    """tf2's ``PoseStamped``: ``pose`` is X_FP, the pose of something P in ``frame_id`` F.

    ``time=None`` means the latest time the buffer has.
    """

    frame_id: str
    time: Optional[float]
    pose: RigidTransform


# ----------------------------------------------------------------------------
# The buffer


@dataclass(frozen=True)
class _Snapshot:
    time: float
    #: X_WB of every body, by body index.
    X_WB: tuple[RigidTransform, ...]


@dataclass(frozen=True)
class _Image:
    """One sample of a camera and the frames it gives: frame name -> (model, X_CM)."""

    image: LogicalCameraImage
    frames: dict[str, tuple[str, RigidTransform]]

    @property
    def time(self) -> float:
        return self.image.time


def detected_frame_name(camera: str, model: str) -> str:
    """The frame of a model a camera sees: ``<camera>_<model>_frame``."""
    return f"{camera}_{model}_frame"


def interpolate_pose(X_a: RigidTransform, X_b: RigidTransform, alpha: float) -> RigidTransform:
    """Linear in translation, slerp in rotation; ``alpha`` = 0 gives X_a, 1 gives X_b."""
    q = X_a.rotation().ToQuaternion().slerp(alpha, X_b.rotation().ToQuaternion())
    p = (1.0 - alpha) * X_a.translation() + alpha * X_b.translation()
    return RigidTransform(q, p)


def _at_or_before(times: list[float], time: float) -> int:
    """Index of the last of the sorted ``times`` <= ``time`` (within TIME_EPS), or -1."""
    return bisect.bisect_right(times, time + TIME_EPS) - 1


class TfBuffer:
    """tf2's buffer over a station: a history of frame poses, looked up by name and time.

    ``record(root_context)`` stores a snapshot at the Context's time: the world
    pose of every named frame of the plant (see :class:`FrameTree`) and the
    last image of every logical camera of the station. Snapshots older than
    ``cache_time`` before the newest one are dropped; a snapshot at the time of
    an existing one replaces it.

    Detected models: each model in a camera's image (with a name: anonymized
    detections get none) is a frame ``<camera>_<model>_frame``, child of
    ``<camera>_frame``, at the pose X_CM the camera reported (noise included),
    stamped with the *image's* time, as the camera would publish it. A camera
    samples and holds, and a simulation stopped at t has not yet taken the
    sample due at t, so the image held at t is up to one camera period older
    than t: asked at t, a detected frame is at its pose in the last image at or
    before t, interpolated towards the next image when that one exists (is held
    by a later snapshot) and also sees the model. A detected frame does not
    exist at t when the last image at or before t does not see its model.

    Lookups between two snapshots interpolate, as tf2 does, each parent -> child
    transform on the path between the two frames (linear in translation, slerp
    in rotation). ``time=None`` means the newest snapshot's time.

    The buffer records values evaluated from the Contexts you give it; it holds
    no Context itself.
    """

    def __init__(self, station: Station, cache_time: float = 10.0):
        if not cache_time > 0 or not math.isfinite(cache_time):
            raise ConfigError(f"cache_time={cache_time!r} is invalid; valid: a finite time > 0 s")
        self._station = station
        self._plant = station.plant
        self._cache_time = float(cache_time)
        self._tree = FrameTree(station.plant)
        #: static frame name -> (body index, X_BF)
        self._static: dict[str, tuple[int, RigidTransform]] = {}
        for name in self._tree.names():
            frame = self._tree.frame(name)
            self._static[name] = (int(frame.body().index()), frame.GetFixedPoseInBodyFrame())
        self._parents: dict[str, Optional[str]] = {n: self._tree.parent(n) for n in self._static}
        self._body_frames = {n for n in self._static if self._tree.frame(n).is_body_frame()}
        self._cameras: tuple[str, ...] = tuple(station.cameras)
        for camera in self._cameras:
            if f"{camera}_frame" not in self._static:
                raise ConfigError(f"camera {camera!r} has no plant frame {camera}_frame")
        self._snapshots: list[_Snapshot] = []
        self._times: list[float] = []
        #: camera -> its distinct images, oldest first, and their times
        self._images: dict[str, list[_Image]] = {c: [] for c in self._cameras}
        self._image_times: dict[str, list[float]] = {c: [] for c in self._cameras}

    @classmethod
    def from_context(cls, station: Station, root_context: Context, cache_time: float = 10.0) -> TfBuffer:
        """A buffer holding one snapshot of ``root_context`` (for static queries)."""
        buffer = cls(station, cache_time)
        buffer.record(root_context)
        return buffer

    # ------------------------------------------------------------------ recording

    @property
    def cache_time(self) -> float:
        return self._cache_time

    @property
    def times(self) -> tuple[float, ...]:
        """The times of the snapshots held, oldest first."""
        return tuple(self._times)

    @property
    def cameras(self) -> tuple[str, ...]:
        return self._cameras

    def record(self, root_context: Context) -> None:
        """Stores a snapshot of ``root_context`` (the station's Context, or that
        of a diagram containing the station) at the Context's time."""
        time = root_context.get_time()
        plant_context = self._plant.GetMyContextFromRoot(root_context)
        X_WB = tuple(self._plant.get_body_poses_output_port().Eval(plant_context))
        station_context = self._station.diagram.GetMyContextFromRoot(root_context)
        i = bisect.bisect_left(self._times, time - TIME_EPS)
        if i < len(self._times) and abs(self._times[i] - time) <= TIME_EPS:
            self._snapshots[i] = _Snapshot(time, X_WB)
        else:
            self._snapshots.insert(i, _Snapshot(time, X_WB))
            self._times.insert(i, time)
        for camera in self._cameras:
            image = self._station.diagram.GetOutputPort(f"{camera}.image").Eval(station_context)
            self._add_image(camera, image)
        self._trim()

    def _add_image(self, camera: str, image: LogicalCameraImage) -> None:
        if not math.isfinite(image.time):
            return  # the camera has not sampled yet
        frames: dict[str, tuple[str, RigidTransform]] = {}
        for model in image.models:
            if not model.name:
                continue  # anonymized: no frame
            name = detected_frame_name(camera, model.name)
            if name in self._static:
                _log.warning(
                    "%s sees %r but a plant frame is already called %s; no frame for the detection",
                    camera,
                    model.name,
                    name,
                )
                continue
            frames[name] = (model.name, model.X_CM)
        times = self._image_times[camera]
        i = bisect.bisect_left(times, image.time - TIME_EPS)
        if i < len(times) and abs(times[i] - image.time) <= TIME_EPS:
            self._images[camera][i] = _Image(image, frames)
        else:
            self._images[camera].insert(i, _Image(image, frames))
            times.insert(i, image.time)

    def _trim(self) -> None:
        """Drops snapshots older than cache_time, and images older than the one
        the oldest snapshot holds."""
        drop = bisect.bisect_left(self._times, self._times[-1] - self._cache_time - TIME_EPS)
        if drop:
            del self._snapshots[:drop]
            del self._times[:drop]
        for camera in self._cameras:
            keep_from = _at_or_before(self._image_times[camera], self._times[0])
            if keep_from > 0:
                del self._images[camera][:keep_from]
                del self._image_times[camera][:keep_from]

    def monitor(self, period: float = 0.1) -> Callable[[Context], EventStatus]:
        """A Simulator monitor (``simulator.set_monitor(buffer.monitor(0.05))``)
        that records a snapshot every ``period`` seconds of simulated time (at
        the first step at or after each multiple of ``period``)."""
        if not period > 0 or not math.isfinite(period):
            raise ConfigError(f"period={period!r} is invalid; valid: a finite time > 0 s")

        def record_every_period(root_context: Context) -> EventStatus:
            t = root_context.get_time()
            if not self._times or math.floor((t + TIME_EPS) / period) > math.floor(
                (self._times[-1] + TIME_EPS) / period
            ):
                self.record(root_context)
            return EventStatus.Succeeded()

        return record_every_period

    def clear(self) -> None:
        """Forgets everything recorded."""
        self._snapshots.clear()
        self._times.clear()
        for camera in self._cameras:
            self._images[camera].clear()
            self._image_times[camera].clear()

    # ------------------------------------------------------------------ queries

    def all_frame_names(self, time: Optional[float] = None) -> list[str]:
        """Every frame at ``time`` (None: the latest), detected frames included, sorted."""
        return sorted([*self._static, *self._detected_at(self._resolve_time(time))])

    def edges(self, time: Optional[float] = None) -> list[tuple[str, str]]:
        """(parent, child) pairs of the tree at ``time`` (None: the latest)."""
        detected = self._detected_at(self._resolve_time(time))
        return self._tree.edges() + [(f"{camera}_frame", name) for name, camera in sorted(detected.items())]

    def parent(self, name: str) -> Optional[str]:
        """The parent of frame ``name`` (None for ``world``)."""
        self._check_name(name)
        if name in self._static:
            return self._parents[name]
        return f"{self._camera_of(name)}_frame"

    def image(self, camera: str, time: Optional[float] = None) -> LogicalCameraImage:
        """The image ``camera`` held at ``time`` (None: latest): its last sample at or before."""
        if camera not in self._cameras:
            raise UnknownNameError("camera", camera, self._cameras, closest=True)
        time = self._resolve_time(time)
        i = _at_or_before(self._image_times[camera], time)
        if i < 0:
            raise FrameError(f"{camera} has no image at or before {time:.6g} s")
        return self._images[camera][i].image

    def can_transform(self, target: str, source: str, time: Optional[float] = None) -> bool:
        """Whether :meth:`lookup_transform` would succeed."""
        try:
            self.lookup_transform(target, source, time)
        except (FrameError, UnknownNameError):
            return False
        return True

    def lookup_transform(self, target: str, source: str, time: Optional[float] = None) -> TransformStamped:
        """``X_TS``, the pose of ``source`` in ``target`` at ``time`` (None: the latest).

        Raises:
            UnknownNameError: a name is no frame of the buffer (lists the closest).
            FrameError: ``time`` outside the history; a detected frame the camera
                did not see at that time; nothing recorded yet.
        """
        self._check_name(target)
        self._check_name(source)
        t = self._resolve_time(time)
        i = _at_or_before(self._times, t)
        before = self._snapshots[i]
        after = None
        if abs(before.time - t) > TIME_EPS:
            after = self._snapshots[i + 1]
        cache: dict[str, RigidTransform] = {"world": RigidTransform()}
        X_WT = self._world_pose(target, before, after, t, cache)
        X_WS = self._world_pose(source, before, after, t, cache)
        return TransformStamped(target, source, t, X_WT.InvertAndCompose(X_WS))

    def transform_pose(self, pose: PoseStamped, target_frame: str) -> PoseStamped:
        """``pose`` expressed in ``target_frame`` at the pose's time (tf2's ``buffer.transform``)."""
        stamped = self.lookup_transform(target_frame, pose.frame_id, pose.time)
        return PoseStamped(target_frame, stamped.time, stamped.transform @ pose.pose)

    # ------------------------------------------------------------------ internals

    def _resolve_time(self, time: Optional[float]) -> float:
        """``time`` (None: the newest) checked against the snapshots' range."""
        if not self._snapshots:
            raise FrameError("the tf buffer is empty: record a Context first")
        if time is None:
            return self._times[-1]
        time = float(time)
        oldest, newest = self._times[0], self._times[-1]
        if not (oldest - TIME_EPS <= time <= newest + TIME_EPS):
            raise FrameError(
                f"time {time:.6g} s is outside the tf buffer's history "
                f"[{oldest:.6g}, {newest:.6g}] s ({len(self._times)} snapshots, "
                f"cache_time {self._cache_time:g} s)"
            )
        return min(max(time, oldest), newest)

    def _detected_at(self, time: float) -> dict[str, str]:
        """Detected frame name -> camera, of the images held at ``time``."""
        detected: dict[str, str] = {}
        for camera in self._cameras:
            i = _at_or_before(self._image_times[camera], time)
            if i >= 0:
                detected.update(dict.fromkeys(self._images[camera][i].frames, camera))
        return detected

    def _camera_of(self, name: str) -> Optional[str]:
        """The camera that gives the detected frame ``name`` (None: no image has it)."""
        for camera in self._cameras:
            if any(name in image.frames for image in self._images[camera]):
                return camera
        return None

    def _check_name(self, name: str) -> None:
        if name in self._static or self._camera_of(name) is not None:
            return
        for camera in self._cameras:
            prefix = f"{camera}_"
            if name.startswith(prefix) and name.endswith("_frame") and len(name) > len(prefix) + 6:
                model = name[len(prefix) : -len("_frame")]
                images = self._images[camera]
                seen = sorted({m for image in images for m, _ in image.frames.values()})
                held = (
                    (
                        f"its images from {images[0].time:.6g} to {images[-1].time:.6g} s show "
                        + (", ".join(seen) if seen else "nothing")
                    )
                    if images
                    else "it has no image yet"
                )
                raise FrameError(f"frame {name!r} does not exist: {camera} has not seen {model!r} ({held})")
        known = set(self._static)
        for images in self._images.values():
            for image in images:
                known.update(image.frames)
        raise UnknownNameError("frame", name, known, closest=True)

    def _detection(self, name: str, time: float) -> tuple[str, RigidTransform]:
        """(camera, X_CM) of the detected frame ``name`` at ``time``."""
        camera = self._camera_of(name)
        if camera is None:
            raise UnknownNameError("frame", name, self.all_frame_names(time), closest=True)
        images, times = self._images[camera], self._image_times[camera]
        i = _at_or_before(times, time)
        if i < 0 or name not in images[i].frames:
            seen = [image.time for image in images if name in image.frames]
            model = next(image.frames[name][0] for image in images if name in image.frames)
            held = f"its image at {times[i]:.6g} s" if i >= 0 else "no image yet"
            raise FrameError(
                f"frame {name!r} does not exist at time {time:.6g} s: {camera} did not see "
                f"{model!r} then ({held}; it saw it in {len(seen)} image(s) from "
                f"{min(seen):.6g} to {max(seen):.6g} s)"
            )
        X_CM = images[i].frames[name][1]
        if abs(times[i] - time) > TIME_EPS and i + 1 < len(images) and name in images[i + 1].frames:
            alpha = (time - times[i]) / (times[i + 1] - times[i])
            X_CM = interpolate_pose(X_CM, images[i + 1].frames[name][1], alpha)
        return camera, X_CM

    def _snapshot_world_pose(self, snapshot: _Snapshot, name: str) -> RigidTransform:
        """X_WF of a plant frame in one snapshot."""
        body, X_BF = self._static[name]
        return snapshot.X_WB[body] @ X_BF

    def _world_pose(
        self,
        name: str,
        before: _Snapshot,
        after: Optional[_Snapshot],
        time: float,
        cache: dict[str, RigidTransform],
    ) -> RigidTransform:
        """X_WF at ``time``: from ``before`` alone, or each edge interpolated."""
        if name in cache:
            return cache[name]
        if name in self._static:
            parent = self._parents[name]
            if after is None:
                X = self._snapshot_world_pose(before, name)
            elif parent is None:
                X = RigidTransform()
            else:
                if name in self._body_frames:
                    alpha = (time - before.time) / (after.time - before.time)
                    X_PF = interpolate_pose(
                        self._snapshot_world_pose(before, parent).InvertAndCompose(
                            self._snapshot_world_pose(before, name)
                        ),
                        self._snapshot_world_pose(after, parent).InvertAndCompose(
                            self._snapshot_world_pose(after, name)
                        ),
                        alpha,
                    )
                else:
                    X_PF = self._static[name][1]  # fixed in its body: X_BF
                X = self._world_pose(parent, before, after, time, cache) @ X_PF
        else:
            camera, X_CM = self._detection(name, time)
            X = self._world_pose(f"{camera}_frame", before, after, time, cache) @ X_CM
        cache[name] = X
        return X

    def _frame_kind(self, name: str) -> str:
        """``camera``, ``detected``, ``moving`` (across a joint) or ``fixed``."""
        if name not in self._static:
            return "detected"
        if any(name.startswith(f"{c}_") for c in self._cameras):
            return "camera"
        if self._tree.is_fixed(name):
            return "fixed"
        return "moving"


# ----------------------------------------------------------------------------
# view_frames


_COLOURS = {
    "fixed": ("#f5f6f8", "#8391a7"),
    "moving": ("#cfe0fa", "#1f4e8c"),
    "camera": ("#ffe2c2", "#d2691e"),
    "detected": ("#d5f5d5", "#2e8b57"),
}
_LEGEND = {
    "fixed": "frame (fixed to its parent)",
    "moving": "frame (across a joint)",
    "camera": "logical camera frame",
    "detected": "model seen by a camera",
}


def _wrap(name: str, width: int = 15) -> str:
    """Splits a frame name at underscores into lines of about ``width`` characters."""
    lines: list[str] = []
    for word in name.split("_"):
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += "_" + word
        else:
            if lines:
                lines[-1] += "_"
            lines.append(word)
    return "\n".join(textwrap.fill(line, width + 1) for line in lines)


def _tree_layout(edges: list[tuple[str, str]], root: str) -> tuple[dict[str, tuple[float, int]], int]:
    """Tidy top-down layout: leaves at consecutive x in depth-first order, each
    parent centred over its children. Returns name -> (x, depth) and the leaf count."""
    children: dict[str, list[str]] = {}
    for parent, child in edges:
        children.setdefault(parent, []).append(child)
    for kids in children.values():
        kids.sort()
    position: dict[str, tuple[float, int]] = {}
    next_leaf = 0

    def place(name: str, depth: int) -> float:
        nonlocal next_leaf
        kids = children.get(name, [])
        if not kids:
            x = float(next_leaf)
            next_leaf += 1
        else:
            xs = [place(k, depth + 1) for k in kids]
            x = (xs[0] + xs[-1]) / 2
        position[name] = (x, depth)
        return x

    place(root, 0)
    return position, next_leaf


def _tree_axes(position: dict[str, tuple[float, int]], leaves: int) -> tuple[Figure, Axes]:
    """A figure sized for the layout ``position`` of ``leaves`` leaves, and its
    frameless axes in layout units (x: leaf slots, y: minus the depth)."""
    from matplotlib.figure import Figure

    depth = max(d for _, d in position.values())
    slot, row = 1.25, 0.95  # inches per leaf, per level
    width = max(8.0, slot * leaves + 1.0)
    height = row * (depth + 1) + 1.0
    fig = Figure(figsize=(width, height))
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_xlim(-0.5 - 0.4 / slot, leaves - 0.5 + 0.4 / slot)
    ax.set_ylim(-(depth + 0.5), 0.5 + 0.6 / row)
    ax.axis("off")
    return fig, ax


def _draw_frame_boxes(ax: Axes, buffer: TfBuffer, position: dict[str, tuple[float, int]]) -> dict[str, Text]:
    """One box per frame at its layout position, coloured by its kind; name -> box."""
    fontsize = 8.5
    boxes = {}
    for name, (x, d) in position.items():
        face, edge = _COLOURS[buffer._frame_kind(name)]
        boxes[name] = ax.text(
            x,
            -d,
            _wrap(name),
            ha="center",
            va="center",
            fontsize=fontsize,
            zorder=3,
            bbox=dict(boxstyle="round,pad=0.35", facecolor=face, edgecolor=edge, linewidth=1.2),
        )
    return boxes


def _box_extents(fig: Figure, ax: Axes, boxes: dict[str, Text]) -> dict[str, tuple[float, float]]:
    """Draws ``fig`` (which places the boxes) and returns name -> (bottom, top) of each box, in data units."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()  # places the boxes
    renderer = canvas.get_renderer()
    to_data = ax.transData.inverted()
    extent = {}
    for name, text in boxes.items():
        (_, y0), (_, y1) = to_data.transform(text.get_bbox_patch().get_window_extent(renderer).get_points())
        extent[name] = (min(y0, y1), max(y0, y1))
    return extent


def _draw_connectors(
    ax: Axes,
    buffer: TfBuffer,
    edges: list[tuple[str, str]],
    position: dict[str, tuple[float, int]],
    extent: dict[str, tuple[float, float]],
) -> None:
    """Org-chart connectors: down from the parent, along a bus, an arrow down into each child."""
    from matplotlib.patches import FancyArrowPatch

    children: dict[str, list[str]] = {}
    for parent, child in edges:
        children.setdefault(parent, []).append(child)
    trunk = "#8391a7"
    for parent, kids in children.items():
        x0 = position[parent][0]
        bottom = extent[parent][0]
        bus = min(bottom - 0.12, max(extent[k][1] for k in kids) + 0.16)
        xs = [position[k][0] for k in kids]
        ax.plot([x0, x0], [bottom, bus], color=trunk, linewidth=1.0, zorder=1)
        ax.plot([min(xs + [x0]), max(xs + [x0])], [bus, bus], color=trunk, linewidth=1.0, zorder=1)
        for kid, x1 in zip(kids, xs):
            kind = buffer._frame_kind(kid)
            colour = _COLOURS[kind][1] if kind in ("detected", "moving") else trunk
            ax.add_patch(
                FancyArrowPatch(
                    (x1, bus),
                    (x1, extent[kid][1]),
                    arrowstyle="-|>",
                    mutation_scale=9,
                    color=colour,
                    linewidth=1.5 if kind == "moving" else 1.0,
                    linestyle="--" if kind == "detected" else "-",
                    shrinkA=0,
                    shrinkB=1,
                    zorder=2,
                )
            )


def _draw_heading_and_legend(ax: Axes, heading: str, t: float, frames: int) -> None:
    """The title line (``heading``, time, frame count) top left and the colour legend top right."""
    from matplotlib.patches import Patch

    ax.text(
        0.01,
        0.995,
        f"{heading}  (t = {t:.3f} s, {frames} frames)",
        transform=ax.transAxes,
        ha="left",
        va="top",
        fontsize=13,
        weight="bold",
    )
    ax.legend(
        handles=[Patch(facecolor=f, edgecolor=e, label=_LEGEND[k]) for k, (f, e) in _COLOURS.items()],
        loc="upper right",
        fontsize=9,
        frameon=False,
        ncol=4,
        bbox_to_anchor=(0.995, 0.995),
    )


def _save_pdf_and_png(fig: Figure, path_stem: Path) -> list[Path]:
    """Writes ``<stem>.pdf`` and ``<stem>.png`` (creating the folder); returns their paths."""
    paths = []
    path_stem.parent.mkdir(parents=True, exist_ok=True)
    for suffix in (".pdf", ".png"):
        path = path_stem.parent / (path_stem.name + suffix)
        fig.savefig(path, dpi=100)
        paths.append(path)
    return paths


def view_frames(
    buffer: TfBuffer, path_stem: str | Path, time: Optional[float] = None, *, title: Optional[str] = None
) -> list[Path]:
    """Draws the frame tree at ``time`` (None: latest) into ``<stem>.pdf`` and ``<stem>.png``.

    Like ROS ``view_frames``, with matplotlib (no graphviz): frames are boxes,
    arrows go parent -> child, ``world`` on top. Logical camera frames and the
    frames of the models they see are coloured. Returns the two paths written.
    A ``.pdf`` or ``.png`` suffix of ``path_stem`` is dropped.
    """
    # matplotlib is imported in the helpers: it takes ~0.3 s to import. No pyplot: no global state.
    path_stem = Path(path_stem)
    if path_stem.suffix.lower() in (".pdf", ".png"):
        path_stem = path_stem.with_suffix("")
    edges = buffer.edges(time)
    t = buffer.times[-1] if time is None else float(time)
    position, leaves = _tree_layout(edges, "world")
    fig, ax = _tree_axes(position, leaves)
    boxes = _draw_frame_boxes(ax, buffer, position)
    # Arrows run from the bottom of the parent's box to the top of the child's.
    extent = _box_extents(fig, ax, boxes)
    _draw_connectors(ax, buffer, edges, position, extent)
    _draw_heading_and_legend(ax, title or "Frame tree", t, len(position))
    paths = _save_pdf_and_png(fig, path_stem)
    _log.info("frame tree written to %s", ", ".join(str(p) for p in paths))
    return paths
