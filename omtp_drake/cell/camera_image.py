"""What a logical camera reports: the models in view and the image that holds them.

:class:`LogicalCameraImage` (one sample, shown like ``rostopic echo`` of the
course's ``osrf_gear/LogicalCameraImage`` message) holds :class:`DetectedModel`
rows; :func:`model_type` is a model's type from its name. Frames as in
:mod:`omtp_drake.cell.logical_camera` (``W`` the world, ``C`` the camera, ``M`` a
model's origin).
"""

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from pydrake.math import RigidTransform

from omtp_drake.errors import FrameError

if TYPE_CHECKING:
    from omtp_drake.cell.poses import PoseStamped

_TRAILING_INDEX = re.compile(r"_\d+$")


def model_type(name: str) -> str:
    """A model's name without a trailing ``_<digits>`` (``object_3`` -> ``object``)."""
    return _TRAILING_INDEX.sub("", name)


def _pose_dict(X: RigidTransform) -> dict[str, list[float]]:
    """Translation and quaternion [x, y, z, w] (w >= 0, Drake's canonical form)."""
    q = X.rotation().ToQuaternion()
    # `+ 0.0` turns -0.0 into 0.0.
    return {
        "translation": [float(v) + 0.0 for v in X.translation()],
        "rotation_xyzw": [float(v) + 0.0 for v in (q.x(), q.y(), q.z(), q.w())],
    }


def _pose_lines(X: RigidTransform, indent: str) -> list[str]:
    pose = _pose_dict(X)
    lines = [f"{indent}pose:", f"{indent}  position:"]
    lines += [f"{indent}    {k}: {v!r}" for k, v in zip("xyz", pose["translation"])]
    lines.append(f"{indent}  orientation:")
    lines += [f"{indent}    {k}: {v!r}" for k, v in zip("xyzw", pose["rotation_xyzw"])]
    return lines


@dataclass(frozen=True)
class DetectedModel:
    """One model in view.

    Attributes:
        name: the model instance's name (``""`` when the camera anonymizes).
        type: the name without a trailing ``_<digits>`` (see :func:`model_type`).
        X_CM: pose of the model's origin M (its first body's frame) in the camera frame C.
        visible_fraction: the share of the model's image that is not hidden by
            other geometry (see :class:`~omtp_drake.cell.logical_camera.LogicalCamera`); 1.0 when the camera
            does not test occlusion.
        frame: its tf frame as the camera's plugin names it ("": ``<camera>_<name>_frame``
            for a named model, none for an unnamed one).
        tf_children: frames the plugin broadcasts under the model's frame and not in the
            message, each (name, X_MF) (the course plugin's AGV kit trays).
    """

    name: str
    type: str
    X_CM: RigidTransform
    visible_fraction: float = 1.0
    frame: str = ""
    tf_children: tuple[tuple[str, RigidTransform], ...] = ()


@dataclass(frozen=True)
class LogicalCameraImage:
    """One sample of a logical camera.

    Attributes:
        time: the sample time [s].
        camera_name: the camera's name.
        X_WC: the camera frame's pose in the world at ``time``.
        models: the models in view, in the plant's model-instance order.
        occlusion: whether the camera tested occlusion (each model's
            ``visible_fraction`` was measured; it is printed then).

    Images are values: the poses they hold must not be mutated (copies of an
    image share them).
    """

    time: float
    camera_name: str
    X_WC: RigidTransform
    models: tuple[DetectedModel, ...]
    occlusion: bool = False

    def __deepcopy__(self, memo: dict[int, Any]) -> "LogicalCameraImage":
        # Drake clones abstract state values on every update; an image is immutable.
        return self

    @property
    def frame(self) -> str:
        """The camera frame's name in tf (``<camera>_frame``)."""
        return f"{self.camera_name}_frame"

    def pose_of(self, name: str) -> "PoseStamped":
        """The pose of model ``name`` as reported, in the camera frame, stamped with
        the image's time (for ``TfBuffer.transform_pose``)."""
        from omtp_drake.cell.poses import PoseStamped

        for m in self.models:
            if m.name == name:
                return PoseStamped(self.frame, self.time, m.X_CM)
        raise FrameError(
            f"{self.camera_name} does not see {name!r} in its image at t = {self.time:.6g} s; "
            f"it sees: {', '.join(m.name or '(anonymous)' for m in self.models) or 'nothing'}"
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain data (for JSON/YAML); quaternions are [x, y, z, w] with w >= 0."""
        return {
            "time": self.time,
            "camera_name": self.camera_name,
            "camera_pose": _pose_dict(self.X_WC),
            "models": [
                {
                    "name": m.name,
                    "type": m.type,
                    "pose": _pose_dict(m.X_CM),
                    "visible_fraction": float(m.visible_fraction),
                }
                for m in self.models
            ],
        }

    def __str__(self) -> str:
        """Renders like ``rostopic echo`` of the original ``LogicalCameraImage`` message
        (with occlusion, each model also shows its ``visible_fraction``)."""
        lines = [f"time: {round(self.time, 9)!r}", f'camera_name: "{self.camera_name}"']
        lines += _pose_lines(self.X_WC, "")
        if not self.models:
            lines.append("models: []")
        else:
            lines.append("models:")
            for m in self.models:
                lines += ["  -", f'    name: "{m.name}"', f'    type: "{m.type}"']
                lines += _pose_lines(m.X_CM, "    ")
                if self.occlusion:
                    lines.append(f"    visible_fraction: {round(m.visible_fraction, 4)!r}")
        lines.append("---")
        return "\n".join(lines)
