"""tf2's buffer over a running station: frame poses and camera images with history.

:class:`TfBuffer` ``record(context)`` stores a snapshot (every frame's world
pose and every logical camera's last image); lookups by name and time are
interpolated between snapshots. Besides the plant's frames it knows one frame
per model a logical camera sees, ``<camera>_<model>_frame`` (e.g.
``logical_camera_2_object_1_frame``), child of ``<camera>_frame``, at the pose
the camera reported. ``lookup_transform(target, source)`` has tf2's meaning: it
returns ``X_TS``, the pose of the source frame in the target frame.

Typical use::

    runtime = FactoryRuntime("lecture6_assignment3")
    buffer = TfBuffer(runtime.station)
    runtime.on_tick(lambda rt: buffer.record(rt.context))  # record every tick
    runtime.advance_to(1.5)
    X = buffer.lookup_transform("vacuum_gripper2_suction_cup",
                                "logical_camera_2_object_1_frame").transform
"""

from __future__ import annotations

import bisect
import functools
import json
import logging
import math
from collections.abc import Callable, Collection
from typing import Optional

from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.framework import Context, EventStatus

from omtp_drake.cell.frames import TIME_EPS, FrameTree
from omtp_drake.cell.logical_camera import CameraSample, LogicalCameraImage
from omtp_drake.cell.poses import PoseStamped, TransformStamped, detected_frame_name, interpolate_pose
from omtp_drake.cell.station import Station
from omtp_drake.errors import ConfigError, FrameError, UnknownNameError
from omtp_drake.sim.tf_poses import PlantFramePoses, Snapshot

_log = logging.getLogger(__name__)


class _Image:
    """One sample of a camera, its image and the frames that gives: frame name -> (model,
    X_CM). Both are made when first asked for (an image is a function of its sample, and
    most samples are never looked at): a run pays for the images its lookups read."""

    __slots__ = ("sample", "_make", "_name_frames", "_image", "_frames")

    def __init__(
        self,
        sample: CameraSample,
        make: Callable[[CameraSample], LogicalCameraImage],
        name_frames: Callable[[LogicalCameraImage], dict[str, tuple[str, RigidTransform]]],
    ):
        self.sample = sample
        self._make = make
        self._name_frames = name_frames
        self._image: Optional[LogicalCameraImage] = None
        self._frames: Optional[dict[str, tuple[str, RigidTransform]]] = None

    @property
    def time(self) -> float:
        return self.sample.time

    @property
    def image(self) -> LogicalCameraImage:
        if self._image is None:
            self._image = self._make(self.sample)
        return self._image

    @property
    def frames(self) -> dict[str, tuple[str, RigidTransform]]:
        if self._frames is None:
            self._frames = self._name_frames(self.image)
        return self._frames


def _at_or_before(times: list[float], time: float) -> int:
    """Index of the last of the sorted ``times`` <= ``time`` (within TIME_EPS), or -1."""
    return bisect.bisect_right(times, time + TIME_EPS) - 1


class _DetectedFrames:
    """The cameras' images over time and the frames they give: one frame
    ``<camera>_<model>_frame`` per named model an image sees, at the pose X_CM
    the camera reported (see :class:`TfBuffer`, "Detected models").

    ``static`` are the plant's frame names: a detection whose frame name is
    taken by one gets no frame.
    """

    def __init__(self, cameras: tuple[str, ...], static: Collection[str]):
        self._cameras = cameras
        self._static = static
        #: camera -> the prefix of its detected frames (the plugin's ``model_frame_prefix``)
        self.prefixes = {camera: f"{camera}_" for camera in cameras}
        #: camera -> its distinct images, oldest first, and their times
        self._images: dict[str, list[_Image]] = {c: [] for c in cameras}
        self._image_times: dict[str, list[float]] = {c: [] for c in cameras}

    def add(
        self, camera: str, sample: CameraSample, make: Callable[[CameraSample], LogicalCameraImage]
    ) -> None:
        """Stores ``sample`` of ``camera``, whose image is ``make(sample)`` (one at the same
        time is replaced, unless it is the same sample)."""
        if sample.X_WB is None or not math.isfinite(sample.time):
            return  # the camera has not sampled yet
        times, images = self._image_times[camera], self._images[camera]
        i = bisect.bisect_left(times, sample.time - TIME_EPS)
        if i < len(times) and abs(times[i] - sample.time) <= TIME_EPS:
            if images[i].sample is not sample:
                images[i] = _Image(sample, make, functools.partial(self._frames_of, camera))
        else:
            images.insert(i, _Image(sample, make, functools.partial(self._frames_of, camera)))
            times.insert(i, sample.time)

    def _frames_of(self, camera: str, image: LogicalCameraImage) -> dict[str, tuple[str, RigidTransform]]:
        """The frames ``image`` of ``camera`` gives: one a named model (none for a name a
        plant frame has)."""
        frames: dict[str, tuple[str, RigidTransform]] = {}
        for model in image.models:
            if not model.name and not model.frame:
                continue  # anonymized by the Python layer's camera, or nested: no frame
            name = model.frame or detected_frame_name(camera, model.name)
            if name in self._static:
                _log.warning(
                    "%s sees %r but a plant frame is already called %s; no frame for the detection",
                    camera,
                    model.name,
                    name,
                )
                continue
            frames[name] = (model.name or name, model.X_CM)
            for child, X_MF in model.tf_children:
                if child not in self._static:
                    frames[child] = (model.name or name, model.X_CM @ X_MF)
        return frames

    def trim(self, time: float) -> None:
        """Drops each camera's images older than the one it held at ``time``."""
        for camera in self._cameras:
            keep_from = _at_or_before(self._image_times[camera], time)
            if keep_from > 0:
                del self._images[camera][:keep_from]
                del self._image_times[camera][:keep_from]

    def clear(self) -> None:
        for camera in self._cameras:
            self._images[camera].clear()
            self._image_times[camera].clear()

    def image(self, camera: str, time: float) -> LogicalCameraImage:
        """The image ``camera`` held at ``time``: its last sample at or before."""
        i = _at_or_before(self._image_times[camera], time)
        if i < 0:
            raise FrameError(f"{camera} has no image at or before {time:.6g} s")
        return self._images[camera][i].image

    def at(self, time: float) -> dict[str, str]:
        """Detected frame name -> camera, of the images held at ``time``."""
        detected: dict[str, str] = {}
        for camera in self._cameras:
            i = _at_or_before(self._image_times[camera], time)
            if i >= 0:
                detected.update(dict.fromkeys(self._images[camera][i].frames, camera))
        return detected

    def camera_of(self, name: str) -> Optional[str]:
        """The camera that gives the detected frame ``name`` (None: no image has it)."""
        for camera in self._cameras:
            if any(name in image.frames for image in self._images[camera]):
                return camera
        return None

    def names(self) -> set[str]:
        """Every detected frame any held image gives."""
        return {name for images in self._images.values() for image in images for name in image.frames}

    def check_unseen(self, name: str) -> None:
        """FrameError when ``name`` is a camera's detected-frame name for a model
        none of its held images sees (the error says what they show)."""
        for camera in self._cameras:
            prefix = self.prefixes[camera]
            if prefix and name.startswith(prefix) and name.endswith("_frame") and len(name) > len(prefix) + 6:
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

    def detection(self, name: str, camera: str, time: float) -> RigidTransform:
        """X_CM of the detected frame ``name`` of ``camera`` at ``time``."""
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
        return X_CM


class TfBuffer:
    """tf2's buffer over a station: a history of frame poses, looked up by name and time.

    ``record(root_context)`` stores a snapshot at the Context's time: the world
    pose of every named frame of the plant (see :class:`FrameTree`) and the
    last sample of every logical camera of the station (its image, and the frames
    that gives, are made from the sample when a lookup first reads them: an image
    is a function of its sample, and most are never read). Snapshots older than
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
        self._poses = PlantFramePoses(self._tree)
        #: static frame name -> (body index, X_BF)
        self._static = self._poses.static
        self._cameras: tuple[str, ...] = tuple(station.cameras)
        for camera in self._cameras:
            if f"{camera}_frame" not in self._static:
                raise ConfigError(f"camera {camera!r} has no plant frame {camera}_frame")
        self._snapshots: list[Snapshot] = []
        self._times: list[float] = []
        self._detected = _DetectedFrames(self._cameras, self._static.keys())
        self._camera_systems = [(camera, station.cameras[camera]) for camera in self._cameras]
        #: camera -> how its image of a sample is made (none: the camera's own image_of)
        self._images: dict[str, Callable[[CameraSample], LogicalCameraImage]] = {}

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
        poses = self._plant.get_body_poses_output_port().EvalAbstract(plant_context).Clone()
        i = bisect.bisect_left(self._times, time - TIME_EPS)
        if i < len(self._times) and abs(self._times[i] - time) <= TIME_EPS:
            self._snapshots[i] = Snapshot(time, poses)
        else:
            self._snapshots.insert(i, Snapshot(time, poses))
            self._times.insert(i, time)
        for camera, system in self._camera_systems:
            sample = system.sample(system.GetMyContextFromRoot(root_context))
            self._detected.add(camera, sample, self._images.get(camera) or system.image_of)
        self._trim()

    def use_images(self, images: Callable[[str], Callable[[CameraSample], LogicalCameraImage]]) -> None:
        """Makes each camera's image of a sample with ``images(camera)(sample)`` from now on
        instead of the camera's own (the station's ``<camera>.image``; the ROS layer gives
        the course plugin's model list, whose models get the detected frames, under the
        plugin's ``model_frame_prefix``); the detected frames recorded so far are forgotten."""
        self._images = {camera: images(camera) for camera in self._cameras}
        names = self._station.scenario.plugin_names
        self._detected.prefixes = {c: names.camera_listing(c).frame_prefix(c) for c in self._cameras}
        self._detected.clear()

    def _trim(self) -> None:
        """Drops snapshots older than cache_time, and images older than the one
        the oldest snapshot holds."""
        drop = bisect.bisect_left(self._times, self._times[-1] - self._cache_time - TIME_EPS)
        if drop:
            del self._snapshots[:drop]
            del self._times[:drop]
        self._detected.trim(self._times[0])

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
        self._detected.clear()

    # ------------------------------------------------------------------ queries

    def all_frame_names(self, time: Optional[float] = None) -> list[str]:
        """Every frame at ``time`` (None: the latest), detected frames included, sorted."""
        return sorted([*self._static, *self._detected.at(self._resolve_time(time))])

    def edges(self, time: Optional[float] = None) -> list[tuple[str, str]]:
        """(parent, child) pairs of the tree at ``time`` (None: the latest)."""
        detected = self._detected.at(self._resolve_time(time))
        return self._tree.edges() + [(f"{camera}_frame", name) for name, camera in sorted(detected.items())]

    def detected_frames(self, time: Optional[float] = None) -> dict[str, str]:
        """The detected frames at ``time`` (None: the latest): frame name -> its camera."""
        return dict(self._detected.at(self._resolve_time(time)))

    def parent(self, name: str) -> Optional[str]:
        """The parent of frame ``name`` (None for ``world``)."""
        self._check_name(name)
        if name in self._static:
            return self._poses.parents[name]
        return f"{self._detected.camera_of(name)}_frame"

    def image(self, camera: str, time: Optional[float] = None) -> LogicalCameraImage:
        """The image ``camera`` held at ``time`` (None: latest): its last sample at or before."""
        if camera not in self._cameras:
            raise UnknownNameError("camera", camera, self._cameras, closest=True)
        return self._detected.image(camera, self._resolve_time(time))

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
        X_WT = self._poses.world_pose(target, before, after, t, cache, self._detection)
        X_WS = self._poses.world_pose(source, before, after, t, cache, self._detection)
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

    def _check_name(self, name: str) -> None:
        if name in self._static or self._detected.camera_of(name) is not None:
            return
        self._detected.check_unseen(name)
        raise UnknownNameError("frame", name, set(self._static) | self._detected.names(), closest=True)

    def _detection(self, name: str, time: float) -> tuple[str, RigidTransform]:
        """(camera, X_CM) of the detected frame ``name`` at ``time``."""
        camera = self._detected.camera_of(name)
        if camera is None:
            raise UnknownNameError("frame", name, self.all_frame_names(time), closest=True)
        return camera, self._detected.detection(name, camera, time)

    def frame_kind(self, name: str) -> str:
        """``camera``, ``detected``, ``moving`` (across a joint) or ``fixed``."""
        if name not in self._static:
            return "detected"
        if any(name.startswith(f"{c}_") for c in self._cameras):
            return "camera"
        if self._tree.is_fixed(name):
            return "fixed"
        return "moving"


def format_transform(X: RigidTransform, time: float = 0.0) -> str:
    """``X`` at ``time`` as ROS ``tf_echo`` prints a transform."""
    q = X.rotation().ToQuaternion()
    rpy = RollPitchYaw(X.rotation()).vector()
    t = X.translation()
    return (
        f"At time {time:.3f}\n"
        f"- Translation: [{t[0]:.3f}, {t[1]:.3f}, {t[2]:.3f}]\n"
        f"- Rotation: in Quaternion [{q.x():.3f}, {q.y():.3f}, {q.z():.3f}, {q.w():.3f}]\n"
        f"            in RPY (radian) [{rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}]\n"
        f"            in RPY (degree) [{math.degrees(rpy[0]):.3f}, {math.degrees(rpy[1]):.3f}, "
        f"{math.degrees(rpy[2]):.3f}]"
    )


def transform_json(X: RigidTransform, time: float) -> str:
    """``X`` at ``time`` as one JSON object: ``translation``, ``rotation_xyzw``, ``time``."""
    q = X.rotation().ToQuaternion()
    return json.dumps(
        {
            "translation": [float(v) for v in X.translation()],
            "rotation_xyzw": [q.x(), q.y(), q.z(), q.w()],
            "time": time,
        }
    )
