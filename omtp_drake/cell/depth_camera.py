"""A Gazebo ``camera`` or ``depth`` sensor as Drake's RGB-D rendering, with its point cloud.

:func:`add_depth_camera` turns a sensor of a description's ``<gazebo>`` tags
(:class:`~omtp_drake.scenario.SensorConfig`, checked where it was read) into VTK
images lit as Gazebo's worlds are (:data:`GAZEBO_LIGHTS`; the logical cameras' views of
:mod:`omtp_drake.cell.rgbd` keep theirs), sampled at the sensor's rate, its colour
image with the camera's Gaussian noise and, for a ``depth`` sensor, Drake's
``DepthImageToPointCloud`` of its depth and colour images.

Sampled, rendered when read: at each sample a ``ZeroOrderHold`` keeps the scene's
geometry poses (cheap), and :class:`CameraRender` renders the held scene only when an
image is read (a subscriber, a script, a test), so the images are those of the sample
time while a camera nobody reads costs neither a renderer nor a render. (Holding the
images themselves rendered every sample: a student's 64 x 48 wrist camera made a
belt-script run pay VTK's renderer and a render every 0.1 s for images nobody read.)

Frames (monogram notation): ``L`` is the sensor's link, ``S`` the sensor
(``<pose>`` in L; it looks along +Sx, Gazebo's convention), ``O`` its optical frame
(+Oz forward, +Ox right, +Oy down; REP 103, ``X_CameraOptical``): images and points
are in O, which the URDF names by ``<frame_name>`` (``camera_link_optical``).

Intrinsics as Gazebo's camera: square pixels, ``f = width / (2 tan(horizontal_fov / 2))``,
the image centre at ((width - 1) / 2, (height - 1) / 2) in pixel indices (see
:func:`camera_info` for Drake's renderer's half-pixel convention); colour
and depth are rendered between the clip planes ``near`` and ``far``; depths outside
the plugin's (``min_depth``, ``max_depth``) give no point (0 nearer, ``inf`` farther,
Drake's too-close and too-far values).

Noise. Gazebo's ``<camera><noise>`` perturbs the image's pixel values: each channel
gets Gaussian noise of ``stddev`` (in [0, 1] intensity units, so x 255), drawn from a
generator seeded by the scenario's seed, the sensor and the image's index (the same
seed gives the same images). Depth and points are noiseless, as Gazebo's depth
camera renders them.

.. pydrake_system::

    name: <sensor> (the systems below, not a diagram)
    output_ports:
    - <sensor>.color_image   (ImageRgba8U, noisy)
    - <sensor>.depth_image   (ImageDepth32F, m)
    - <sensor>.point_cloud   (PointCloud in O; depth sensors)
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Optional

import numpy as np
from pydrake.common.value import Value
from pydrake.geometry import (
    ClippingRange,
    ColorRenderCamera,
    DepthRange,
    DepthRenderCamera,
    FramePoseVector,
    LightParameter,
    MakeRenderEngineVtk,
    Meshcat,
    RenderCameraCore,
    RenderEngineVtkParams,
    SceneGraph,
)
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.perception import BaseField, DepthImageToPointCloud, PointCloud
from pydrake.systems.framework import Context, DiagramBuilder, LeafSystem, OutputPort
from pydrake.systems.primitives import ZeroOrderHold
from pydrake.systems.sensors import CameraInfo, ImageDepth32F, ImageRgba8U, PixelType

from omtp_drake.cell.lifetime import weak_method
from omtp_drake.cell.logical_camera import X_CameraOptical
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import SensorConfig

#: The renderer of the models' Gazebo sensors (the logical cameras' views keep their own).
GAZEBO_RENDERER = "gazebo_vtk"
#: Gazebo's default world lighting: the sun (a directional light, world frame, its
#: ``<direction>`` and diffuse 0.8) and the scene's ambient 0.4, here a light from the
#: camera. Drake's default (one light along the camera's axis) leaves a floor seen by
#: a level camera black.
GAZEBO_LIGHTS = (
    LightParameter(type="directional", frame="world", direction=[-0.5, 0.1, -0.9], intensity=0.8),
    LightParameter(type="directional", frame="camera", direction=[0.0, 0.0, 1.0], intensity=0.4),
)


def add_gazebo_renderer(scene_graph: SceneGraph, context: Context) -> None:
    """Adds :data:`GAZEBO_RENDERER` (VTK, Gazebo's lighting) to ``scene_graph``'s ``context``
    unless it has it (the perception geometries registered so far join it)."""
    if not scene_graph.HasRenderer(context, GAZEBO_RENDERER):
        params = RenderEngineVtkParams(lights=list(GAZEBO_LIGHTS), cast_shadows=False)
        scene_graph.AddRenderer(context, GAZEBO_RENDERER, MakeRenderEngineVtk(params))


def camera_info(sensor: SensorConfig, *, pixel_centres_at_integers: bool = True) -> CameraInfo:
    """The intrinsics of ``sensor``'s images (see the module doc), principal point in pixel
    indices (pixel centres at integers: DepthImageToPointCloud's and gazebo_ros's convention).

    With ``pixel_centres_at_integers=False``: the same camera for Drake's renderer, whose
    pixel centres lie at half-integers (a pixel's ray passes through (u + 0.5, v + 0.5));
    the principal point is then half a pixel further on. With one CameraInfo for both, a
    point's depth is read half a pixel off its ray (a floor point 9 m away came out 12 mm
    high at 640 x 480)."""
    camera = _camera(sensor)
    focal = camera.width / (2.0 * math.tan(camera.horizontal_fov / 2.0))
    shift = 0.5 if pixel_centres_at_integers else 0.0
    return CameraInfo(
        width=camera.width,
        height=camera.height,
        focal_x=focal,
        focal_y=focal,
        center_x=camera.width / 2.0 - shift,
        center_y=camera.height / 2.0 - shift,
    )


def depth_range(sensor: SensorConfig) -> tuple[float, float]:
    """The depths (m) the sensor measures: the clip planes cut by the plugin's min/max depth."""
    camera = _camera(sensor)
    low, high = camera.near, camera.far
    plugin = sensor.ros_camera
    if plugin is not None:
        low = max(low, plugin.min_depth)
        high = min(high, plugin.max_depth if plugin.max_depth is not None else math.inf)
    if not low < high:
        raise ConfigError(
            f"sensor {sensor.name!r}: min_depth/max_depth leave no depth between the clip planes "
            f"({camera.near}, {camera.far})"
        )
    return low, high


def _camera(sensor: SensorConfig):
    if sensor.camera is None:
        raise ConfigError(f"sensor {sensor.name!r} ({sensor.type}) has no <camera>")
    return sensor.camera


class ColorNoise(LeafSystem):
    """Gazebo's image noise on a colour image: N(mean, stddev) per channel (intensity units),
    drawn from ``(seed, index of the sensor, index of the image)``.

    Input ``color_image`` (ImageRgba8U); output ``color_image`` (ImageRgba8U)."""

    def __init__(self, mean: float, stddev: float, period: float, seed: int, key: int):
        super().__init__()
        self._mean, self._stddev, self._period = mean, stddev, period
        self._seed = [int(seed), int(key)]
        self._input = self.DeclareAbstractInputPort("color_image", Value(ImageRgba8U()))
        # C++ holds a port's calc: a weak one lets the system be freed (omtp_drake.cell.lifetime).
        self.DeclareAbstractOutputPort("color_image", lambda: Value(ImageRgba8U()), weak_method(self._calc))

    def _calc(self, context: Context, output) -> None:
        image: ImageRgba8U = self._input.Eval(context)
        index = int(math.floor(context.get_time() / self._period + 1e-6))
        rng = np.random.default_rng([*self._seed, index])
        pixels = np.asarray(image.data)
        noise = rng.standard_normal(pixels[..., :3].shape, dtype=np.float32)
        noise *= np.float32(self._stddev * 255.0)
        noise += pixels[..., :3] + np.float32(self._mean * 255.0)
        noisy = ImageRgba8U(image.width(), image.height())
        data = noisy.mutable_data
        data[..., :3] = np.clip(np.rint(noise), 0, 255)
        data[..., 3] = pixels[..., 3]
        output.set_value(noisy)


class CameraRender(LeafSystem):
    """A camera's colour and depth images, rendered when read, of the scene at the
    geometry poses it is given: those the sensor sampled (held at its rate) or the live
    ones. It renders on a SceneGraph context of its own where :data:`GAZEBO_RENDERER`
    is added at the first image read, so a cell whose camera nobody reads builds no
    renderer and renders nothing; the images are those Drake's
    ``RgbdSensor`` renders at the same poses (``QueryObject.Render*Image`` at the
    sensor's pose ``X_PO`` in its parent frame P). Before the first sample (no pose of
    P) both images are blank, a hold's initial value. The scene is the geometry as the
    SceneGraph's model holds it, at the given poses (the cell changes only proximity
    roles in a Context, never what a camera sees).

    That scene context is a member, not a cache entry: it holds no state (each render
    sets all of its poses first, so any Context may use it), and a Python value in a
    Context aborts the process when C++ frees that Context without the GIL (Drake's
    ``JointSliders.Run`` does, under ``omtp-drake view``). A lock makes each render's
    poses and image one step, should two Contexts of one diagram render at once.

    .. pydrake_system::

        name: CameraRender
        input_ports:
        - sampled_poses   (FramePoseVector: X_WF of the plant's frames, as sampled)
        - geometry_pose   (FramePoseVector: now)
        output_ports:
        - color_image       (ImageRgba8U)
        - depth_image_32f   (ImageDepth32F, m)
        - body_pose_in_world  (RigidTransform X_WO, now)
    """

    def __init__(self, scene_graph: SceneGraph, source, parent, X_PO: RigidTransform, color, depth):
        super().__init__()
        self._scene_graph, self._source = scene_graph, source
        self._parent, self._X_PO = parent, X_PO
        self._color, self._depth = color, depth
        self._size = size = (color.core().intrinsics().width(), color.core().intrinsics().height())
        poses = Value(FramePoseVector())
        self._sampled = self.DeclareAbstractInputPort("sampled_poses", poses)
        self._now = self.DeclareAbstractInputPort("geometry_pose", poses)
        self._scene: Optional[Context] = None  # (made at the first render; see the class doc)
        self._scene_lock = threading.Lock()
        sampled = {self.input_port_ticket(self._sampled.get_index())}
        # C++ holds a port's calc: a weak one lets the system be freed (omtp_drake.cell.lifetime).
        self.DeclareAbstractOutputPort(
            "color_image", lambda: Value(ImageRgba8U(*size)), weak_method(self._calc_color), sampled
        )
        self.DeclareAbstractOutputPort(
            "depth_image_32f", lambda: Value(ImageDepth32F(*size)), weak_method(self._calc_depth), sampled
        )
        self.DeclareAbstractOutputPort(
            "body_pose_in_world",
            lambda: Value(RigidTransform()),
            weak_method(self._calc_pose),
            {self.input_port_ticket(self._now.get_index())},
        )

    def has_renderer(self) -> bool:
        """Whether this camera has rendered an image (and so made its renderer), ever."""
        return self._scene is not None

    def _render(self, context: Context, camera, image_type):
        """The image of ``camera`` (``query.Render*Image`` by type) of the scene at the
        sampled poses; a blank ``image_type`` before the first sample."""
        poses: FramePoseVector = self._sampled.Eval(context)
        if not poses.has_id(self._parent):
            return image_type(*self._size)
        with self._scene_lock:
            if self._scene is None:
                self._scene = self._scene_graph.CreateDefaultContext()
                add_gazebo_renderer(self._scene_graph, self._scene)
            self._scene_graph.get_source_pose_port(self._source).FixValue(self._scene, poses)
            query = self._scene_graph.get_query_output_port().Eval(self._scene)
            if isinstance(camera, ColorRenderCamera):
                return query.RenderColorImage(camera, self._parent, self._X_PO)
            return query.RenderDepthImage(camera, self._parent, self._X_PO)

    def _calc_color(self, context: Context, output) -> None:
        output.set_value(self._render(context, self._color, ImageRgba8U))

    def _calc_depth(self, context: Context, output) -> None:
        output.set_value(self._render(context, self._depth, ImageDepth32F))

    def _calc_pose(self, context: Context, output) -> None:
        output.set_value(self._now.Eval(context).value(self._parent) @ self._X_PO)


@dataclass
class DepthCamera:
    """A built sensor: its settings, the model it is on, and its output ports."""

    config: SensorConfig
    model: str
    info: CameraInfo
    color_image: OutputPort
    depth_image: OutputPort
    #: ``X_WO`` of the optical frame (the sensor's body pose output).
    pose: OutputPort
    point_cloud: Optional[OutputPort] = None


def add_depth_camera(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    instance: ModelInstanceIndex,
    model: str,
    sensor: SensorConfig,
    *,
    seed: int,
    key: int,
    sampled: bool = True,
) -> DepthCamera:
    """Adds ``sensor`` (on a link of model ``instance``, named ``model``) to the diagram:
    its :class:`CameraRender` of the scene as sampled at its rate, the noisy colour
    image and (a ``depth`` sensor) the point cloud. ``key`` tells the sensors' noise
    apart. ``sampled=False``: images of the scene as it is when read (a model viewed,
    not simulated)."""
    camera = _camera(sensor)
    link = plant.GetBodyByName(sensor.link, instance)
    parent = plant.GetBodyFrameIdIfExists(link.index())
    if parent is None:
        raise ConfigError(f"sensor {sensor.name!r}: link {sensor.link!r} has no geometry frame")
    info = camera_info(sensor)
    render_info = camera_info(sensor, pixel_centres_at_integers=False)
    clipping = ClippingRange(camera.near, camera.far)
    core = RenderCameraCore(GAZEBO_RENDERER, render_info, clipping, RigidTransform())
    color = ColorRenderCamera(core, False)
    depth = DepthRenderCamera(core, DepthRange(*depth_range(sensor)))
    X_LS = RigidTransform(RollPitchYaw(sensor.rpy), sensor.xyz)
    X_PO = X_LS @ X_CameraOptical()
    source = plant.get_source_id()
    render = CameraRender(scene_graph, source, parent, X_PO, color, depth)
    rgbd = builder.AddNamedSystem(f"{sensor.name}.rgbd", render)
    poses = plant.get_geometry_pose_output_port()
    builder.Connect(poses, rgbd.GetInputPort("geometry_pose"))
    period = 1.0 / sensor.rate
    if sampled:
        hold = builder.AddNamedSystem(
            f"{sensor.name}.pose_hold", ZeroOrderHold(period, Value(FramePoseVector()))
        )
        builder.Connect(poses, hold.get_input_port())
        poses = hold.get_output_port()
    builder.Connect(poses, rgbd.GetInputPort("sampled_poses"))
    color_out, depth_out = rgbd.GetOutputPort("color_image"), rgbd.GetOutputPort("depth_image_32f")
    if camera.noise_type == "gaussian" and camera.noise_stddev > 0:
        noise = builder.AddNamedSystem(
            f"{sensor.name}.noise", ColorNoise(camera.noise_mean, camera.noise_stddev, period, seed, key)
        )
        builder.Connect(color_out, noise.get_input_port())
        color_out = noise.get_output_port()
    handles = DepthCamera(sensor, model, info, color_out, depth_out, rgbd.GetOutputPort("body_pose_in_world"))
    if sensor.type == "depth":
        cloud = builder.AddNamedSystem(
            f"{sensor.name}.point_cloud",
            DepthImageToPointCloud(info, PixelType.kDepth32F, 1.0, BaseField.kXYZs | BaseField.kRGBs),
        )
        builder.Connect(depth_out, cloud.depth_image_input_port())
        builder.Connect(color_out, cloud.color_image_input_port())
        handles.point_cloud = cloud.point_cloud_output_port()
    return handles


class FinitePoints(LeafSystem):
    """The finite points of a point cloud, with their fields: a depth image's pixels with no
    depth (``inf`` beyond ``max_depth``, 0 nearer than ``min_depth``) give points at infinity or
    NaN, which Meshcat draws nowhere yet is sent (the tutorial robot's camera: over half of its
    307,200 points, 7.4 MB of its view's 12.7 MB replay, which chromium decodes).

    Ports: ``cloud`` (PointCloud) -> ``finite`` (PointCloud)."""

    def __init__(self) -> None:
        super().__init__()
        self._cloud = self.DeclareAbstractInputPort("cloud", Value(PointCloud()))
        self.DeclareAbstractOutputPort("finite", lambda: Value(PointCloud()), weak_method(self._calc))

    def _calc(self, context: Context, output: Value) -> None:
        big = float(np.finfo(np.float32).max)  # inf and NaN are outside; every float32 inside
        output.set_value(self._cloud.Eval(context).Crop(np.full(3, -big), np.full(3, big)))


def show_point_cloud(builder: DiagramBuilder, meshcat: Meshcat, camera: DepthCamera) -> None:
    """Shows ``camera``'s point cloud (its finite points) in Meshcat at ``/drake/<sensor>/points``,
    at its rate."""
    if camera.point_cloud is None:
        return
    from pydrake.geometry import MeshcatPointCloudVisualizer

    finite = builder.AddNamedSystem(f"{camera.config.name}.finite_points", FinitePoints())
    visualizer = builder.AddNamedSystem(
        f"{camera.config.name}.cloud_view",
        MeshcatPointCloudVisualizer(meshcat, f"{camera.config.name}/points", 1.0 / camera.config.rate),
    )
    builder.Connect(camera.point_cloud, finite.get_input_port())
    builder.Connect(finite.get_output_port(), visualizer.cloud_input_port())
    builder.Connect(camera.pose, visualizer.pose_input_port())


def add_model_cameras(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    models: dict[str, ModelInstanceIndex],
    configs: list,
    *,
    seed: int,
    meshcat: Optional[Meshcat] = None,
) -> dict[str, DepthCamera]:
    """Every camera and depth sensor of the described models ``configs`` (ModelConfig,
    added as ``models``), its ports exported as ``<sensor>.color_image``,
    ``<sensor>.depth_image`` and ``<sensor>.point_cloud``; its points shown in ``meshcat``."""
    cameras: dict[str, DepthCamera] = {}
    for model in configs:
        for sensor in model.gazebo.cameras():
            if sensor.name in cameras:
                raise ConfigError(f"{model.file}: sensor name {sensor.name!r} is taken by another model's")
            instance = models[model.name]
            key = len(cameras)
            camera = add_depth_camera(
                builder, plant, scene_graph, instance, model.name, sensor, seed=seed, key=key
            )
            builder.ExportOutput(camera.color_image, f"{sensor.name}.color_image")
            builder.ExportOutput(camera.depth_image, f"{sensor.name}.depth_image")
            if camera.point_cloud is not None:
                builder.ExportOutput(camera.point_cloud, f"{sensor.name}.point_cloud")
                if meshcat is not None:
                    show_point_cloud(builder, meshcat, camera)
            cameras[sensor.name] = camera
    return cameras
