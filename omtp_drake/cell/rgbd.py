"""The RGB-D view of a logical camera: colour, depth and label images rendered by VTK.

A logical camera (:mod:`omtp_drake.cell.logical_camera`) reports names and poses;
its RGB-D view shows the same frustum as images, from Drake's ``RgbdSensor``
on a ``RenderEngineVtk`` (headless: the pip wheel renders without a display).
It is added per camera (``rgbd: true`` in the scenario, ``rgbd_width`` pixels
wide) and the renderer is added to the SceneGraph only when some camera asks
for a view: a station without one has no renderer and renders nothing.

Frames (monogram notation, ``X_AB`` is the pose of frame B in frame A):

* ``C``: the logical camera's frame (it looks along +Cx, Gazebo's convention).
* ``O``: its optical frame, :func:`~omtp_drake.cell.logical_camera.X_CameraOptical`
  (+Oz forward, +Ox right, +Oy down): the frame of the sensor's images.
* ``P``: the body the camera frame is fixed to (the sensor's parent frame).

Intrinsics: the frustum's horizontal fov spans the image width and its
vertical half-extent (``tan(fov / 2) / aspect_ratio``) the image height, so a
point projects to the pixel (u, v) = (cx + fx X / Z, cy + fy Y / Z) of its
position (X, Y, Z) in O, pixel centres at integers. The depth range is the
camera's [``near``, ``far``]; the colour and label images show the cell beyond
``far`` too, up to :data:`CLIPPING_FAR`, as a camera would.

Images (``pydrake.systems.sensors``): colour ``ImageRgba8U``; depth
``ImageDepth32F`` in metres along +Oz (``inf`` beyond ``far``, 0 nearer than
``near``); label ``ImageLabel16I``, each pixel the label of the geometry seen
there: the MultibodyPlant's default, the index of the geometry's body
(:func:`body_label`), or ``RenderLabel.kEmpty`` where nothing is.

The sensor renders when an output is evaluated, at the Context's time (it is
not sampled like the logical camera's list): read it right after the
logical camera's sample to put the two side by side.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
from pydrake.geometry import (
    ClippingRange,
    ColorRenderCamera,
    DepthRange,
    DepthRenderCamera,
    MakeRenderEngineVtk,
    RenderCameraCore,
    RenderEngineVtkParams,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import Body, Frame
from pydrake.systems.framework import Context, Diagram, DiagramBuilder
from pydrake.systems.sensors import CameraInfo, ImageRgba8U, RgbdSensor

from omtp_drake.cell.logical_camera import X_CameraOptical
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import LogicalCameraConfig

_log = logging.getLogger(__name__)

#: The SceneGraph renderer the RGB-D views share.
RENDERER_NAME = "omtp_vtk"
#: The far clipping plane of the colour and label images [m] (at least the
#: camera's ``far``): the cell's floor is 20 m wide, its diagonal under 30 m.
CLIPPING_FAR = 30.0


def camera_info(config: LogicalCameraConfig) -> CameraInfo:
    """The intrinsics of ``config``'s RGB-D view: ``rgbd_width`` x ``rgbd_height()``
    pixels spanning exactly the frustum's horizontal fov and its vertical extent."""
    width, height = config.rgbd_width, config.rgbd_height()
    tan_y = math.tan(config.horizontal_fov / 2)  # half-width / depth
    tan_z = tan_y / config.aspect_ratio  # half-height / depth
    return CameraInfo(
        width=width,
        height=height,
        focal_x=width / 2 / tan_y,
        focal_y=height / 2 / tan_z,
        center_x=width / 2 - 0.5,
        center_y=height / 2 - 0.5,
    )


def render_cameras(config: LogicalCameraConfig) -> tuple[ColorRenderCamera, DepthRenderCamera]:
    """The colour (and label) and the depth camera of ``config``'s RGB-D view, on
    :data:`RENDERER_NAME`, the sensor at O (X_BS = identity): clipped at ``near``
    and :data:`CLIPPING_FAR`, depth measured between ``near`` and ``far``."""
    clipping = ClippingRange(config.near, max(config.far, CLIPPING_FAR))
    core = RenderCameraCore(RENDERER_NAME, camera_info(config), clipping, RigidTransform())
    return ColorRenderCamera(core, False), DepthRenderCamera(core, DepthRange(config.near, config.far))


def add_renderer(scene_graph: SceneGraph) -> bool:
    """Adds the VTK renderer :data:`RENDERER_NAME` to ``scene_graph`` unless it has
    it (the geometries already registered with a perception role join it).
    Returns whether it was added."""
    if scene_graph.HasRenderer(RENDERER_NAME):
        return False
    scene_graph.AddRenderer(RENDERER_NAME, MakeRenderEngineVtk(RenderEngineVtkParams()))
    _log.debug("added renderer %s", RENDERER_NAME)
    return True


def add_rgbd_view(
    builder: DiagramBuilder,
    plant: MultibodyPlant,
    scene_graph: SceneGraph,
    frame: Frame,
    config: LogicalCameraConfig,
) -> RgbdSensor:
    """Adds the RGB-D view of the logical camera ``config`` whose camera frame C is
    ``frame`` (a frame of ``plant``): an ``RgbdSensor`` named ``<camera>.rgbd`` at
    the optical frame O of C, connected to the SceneGraph's query object, and the
    renderer if the SceneGraph lacks it.

    .. pydrake_system::

        name: RgbdSensor
        input_ports:
        - geometry_query
        output_ports:
        - color_image
        - depth_image_32f
        - depth_image_16u
        - label_image
        - body_pose_in_world
        - image_time

    ``config`` is the logical camera's, checked where it was loaded (the scenario,
    or :func:`~omtp_drake.cell.logical_camera.add_logical_camera`).

    Raises:
        ConfigError: a frame not fixed to a body with a geometry frame.
    """
    body: Body = frame.body()
    parent = plant.GetBodyFrameIdIfExists(body.index())
    if parent is None:
        raise ConfigError(
            f"logical camera {config.name!r}: frame {frame.name()!r} is on body {body.name()!r}, "
            "which has no geometry frame; valid: a frame of a plant registered with the SceneGraph"
        )
    color, depth = render_cameras(config)
    add_renderer(scene_graph)
    X_PO = frame.GetFixedPoseInBodyFrame() @ X_CameraOptical()
    sensor = builder.AddNamedSystem(f"{config.name}.rgbd", RgbdSensor(parent, X_PO, color, depth))
    builder.Connect(scene_graph.get_query_output_port(), sensor.query_object_input_port())
    return sensor


def color_image(diagram: Diagram, root_context: Context, camera: str) -> ImageRgba8U:
    """The colour image of ``camera``'s RGB-D view now, from the station ``diagram``'s
    port ``<camera>.color_image`` (``root_context``: the Context of the diagram or
    of one containing it).

    Raises:
        ConfigError: ``camera`` has no RGB-D view (the message says how to add one).
    """
    port = f"{camera}.color_image"
    if not diagram.HasOutputPort(port):
        raise ConfigError(
            f"camera {camera!r} has no RGB-D view (no port {port!r}); valid: a camera with "
            "`rgbd: true` in the scenario"
        )
    return diagram.GetOutputPort(port).Eval(diagram.GetMyContextFromRoot(root_context))


def body_label(body: Body) -> int:
    """The label the plant gives the visual geometries of ``body`` (its index)."""
    return int(body.index())


def rgba_array(image: ImageRgba8U) -> np.ndarray:
    """A colour image as a (height, width, 4) uint8 array (a copy)."""
    return np.array(image.data, dtype=np.uint8, copy=True).reshape(image.height(), image.width(), 4)


def save_png(image: ImageRgba8U, path: str | Path) -> Path:
    """Writes a colour image as a PNG file; returns its path."""
    from matplotlib.image import imsave

    path = Path(path)
    imsave(path, rgba_array(image))
    return path
