"""A logical camera's settings (part of the scenario YAML schema).

The camera system that applies them is :class:`omtp_drake.cell.logical_camera.LogicalCamera`.
"""

import math
from dataclasses import dataclass, field
from typing import Optional

from pydrake.common.schema import Transform
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.errors import ConfigError, check_rate


@dataclass
class LogicalCameraConfig:
    """Parameters of one logical camera (part of the scenario YAML schema).

    Attributes:
        name: the camera's name; also the system's name.
        parent: the name of the plant frame the camera is attached to.
        xyz: camera position in ``parent`` [m].
        rpy: camera orientation in ``parent``, roll-pitch-yaw [rad].
        near: distance of the near clipping plane along +Cx [m].
        far: distance of the far clipping plane along +Cx [m].
        horizontal_fov: full horizontal opening angle (about Cz) [rad].
        aspect_ratio: image width / height; the vertical half-extent of the
            frustum is the horizontal half-extent divided by it.
        update_rate_hz: sampling rate [Hz]; samples at t = k / rate.
        position_noise_sigma: std. dev. of the Gaussian noise added to each
            axis of a reported position (in the camera frame) [m]; 0 = off.
        orientation_noise_sigma: std. dev. of the Gaussian roll, pitch and yaw
            of the rotation that perturbs a reported orientation [rad]; 0 = off.
        known_types: report only models of these types, or of ``known_names``;
            both empty = every model (the course plugin's ``known_model_types``).
        known_names: report only models of these names, or of ``known_types``;
            both empty = every model (the plugin's ``known_model_names``).
        anonymize: report every model with an empty name (its type is kept).
        seed: noise seed of this camera; ``None`` = the scenario's seed.
        occlusion: report a model only when at least ``min_visible_fraction``
            of it is visible from the camera (not hidden by other geometry;
            see :class:`LogicalCamera`); off, every model in view counts as
            fully visible and costs nothing more.
        min_visible_fraction: the smallest visible share of a model's image
            that is reported (with ``occlusion``), in [0, 1].
        rgbd: add an RGB-D view at the camera's pose (colour, depth and label
            images rendered by VTK; see :mod:`omtp_drake.cell.rgbd`).
        rgbd_width: width of the RGB-D images [pixels]; their height is
            ``round(rgbd_width / aspect_ratio)``.
        housing: draw the cell's stand-in housing on the camera's frame; off
            where a world's camera model writes its own visuals and collisions
            (they are loaded as written, a model entry on ``<name>_frame``).
    """

    name: str = "logical_camera"
    parent: str = "world"
    xyz: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    #: The pose in ``parent`` as a ``schema::Transform`` instead of ``xyz`` /
    #: ``rpy``; the scenario loader turns it into them.
    pose: Optional[Transform] = None
    near: float = 0.2
    far: float = 1.0
    horizontal_fov: float = 1.1
    aspect_ratio: float = 1.5
    update_rate_hz: float = 10.0
    position_noise_sigma: float = 0.0
    orientation_noise_sigma: float = 0.0
    known_types: list[str] = field(default_factory=list)
    known_names: list[str] = field(default_factory=list)
    anonymize: bool = False
    seed: Optional[int] = None
    occlusion: bool = False
    min_visible_fraction: float = 0.05
    rgbd: bool = False
    rgbd_width: int = 320
    housing: bool = True

    def validate(self) -> None:
        """Raises ConfigError naming the first invalid field, its value and the valid range."""
        prefix = f"logical camera {self.name!r}:"
        if not self.name:
            raise ConfigError(f"logical camera: name={self.name!r} is invalid; valid: a non-empty string")
        for key in ("xyz", "rpy"):
            value = getattr(self, key)
            if len(value) != 3 or not all(math.isfinite(v) for v in value):
                raise ConfigError(f"{prefix} {key}={value!r} is invalid; valid: 3 finite numbers")
        _check(prefix, "near", self.near, self.near > 0, "near > 0")
        _check(prefix, "far", self.far, self.far > self.near, f"far > near (= {self.near})")
        _check(
            prefix,
            "horizontal_fov",
            self.horizontal_fov,
            0 < self.horizontal_fov < math.pi,
            "0 < horizontal_fov < pi",
        )
        _check(prefix, "aspect_ratio", self.aspect_ratio, self.aspect_ratio > 0, "aspect_ratio > 0")
        check_rate(f"{prefix} update_rate_hz", self.update_rate_hz)
        for key in ("position_noise_sigma", "orientation_noise_sigma"):
            value = getattr(self, key)
            _check(prefix, key, value, value >= 0, f"{key} >= 0")
        if self.seed is not None and self.seed < 0:
            raise ConfigError(f"{prefix} seed={self.seed!r} is invalid; valid: null or seed >= 0")
        _check(
            prefix,
            "min_visible_fraction",
            self.min_visible_fraction,
            0 <= self.min_visible_fraction <= 1,
            "0 <= min_visible_fraction <= 1",
        )
        _check(
            prefix,
            "rgbd_width",
            self.rgbd_width,
            float(self.rgbd_width).is_integer()
            and 16 <= self.rgbd_width <= 4096
            and 1 <= self.rgbd_height() <= 4096,
            "an integer 16 <= rgbd_width <= 4096 with 1 <= rgbd_width / aspect_ratio <= 4096",
        )

    def rgbd_height(self) -> int:
        """Height of the RGB-D images [pixels]: ``rgbd_width / aspect_ratio``, rounded."""
        return max(0, round(self.rgbd_width / self.aspect_ratio)) if self.aspect_ratio > 0 else 0

    def X_PC(self) -> RigidTransform:
        """The camera frame's pose in its parent frame, from ``xyz`` and ``rpy``."""
        return RigidTransform(RollPitchYaw(self.rpy), self.xyz)


def _check(prefix: str, key: str, value: float, ok: bool, valid: str) -> None:
    # `ok` is False for NaN in every comparison used above; infinities are also rejected.
    if not ok or not math.isfinite(value):
        raise ConfigError(f"{prefix} {key}={value!r} is invalid; valid: {valid} (finite)")
