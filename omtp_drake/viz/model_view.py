"""``omtp-drake view``: a description file's model in Meshcat, as rviz with joint_state_publisher_gui.

The URDF tutorial looks at its robot in rviz, moving each joint with a slider of
``joint_state_publisher_gui``, and at its depth camera's image and point cloud. Here:
:func:`build_model_view` puts the model alone in a plant (its root fixed where it is,
as rviz's fixed frame; the URDF's own colours, not Gazebo's), Drake's ``JointSliders``
in Meshcat's panel (one slider per movable joint, within its limits), and for each
camera or depth sensor its images on panels above the model (colour; depth in grey,
near is dark) and a depth sensor's point cloud at ``/drake/<sensor>/points``, all
redrawn when a slider moves. :func:`model_info` is what ``view --json`` lists.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

import numpy as np
from pydrake.common.value import Value
from pydrake.geometry import Mesh, Meshcat, MeshcatVisualizer, MeshcatVisualizerParams, Role, SceneGraph
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.meshcat import JointSliders
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, MultibodyPlant
from pydrake.multibody.tree import BodyIndex, Joint, ModelInstanceIndex
from pydrake.systems.framework import Context, Diagram, DiagramBuilder, LeafSystem
from pydrake.systems.sensors import ImageDepth32F, ImageRgba8U

from omtp_drake.cell.depth_camera import DepthCamera, add_depth_camera, show_point_cloud
from omtp_drake.cell.described_models import add_described_models
from omtp_drake.errors import ConfigError, UnknownNameError
from omtp_drake.scenario import ModelConfig

#: Width (m) of an image panel in the scene.
PANEL_WIDTH = 0.8

#: URDF's names of Drake's joint types.
_URDF_TYPES = {
    "revolute": "revolute",
    "prismatic": "prismatic",
    "weld": "fixed",
    "quaternion_floating": "floating",
    "rpy_floating": "floating",
    "planar": "planar",
    "ball_rpy": "ball",
}


@dataclass
class ModelView:
    """A model in Meshcat with a slider per movable joint (see the module doc)."""

    model: ModelConfig
    meshcat: Meshcat
    diagram: Diagram
    context: Context
    plant: MultibodyPlant
    instance: ModelInstanceIndex
    sliders: JointSliders
    cameras: dict[str, DepthCamera] = field(default_factory=dict)

    def publish(self) -> None:
        """Draws the model, images and points at the sliders' positions."""
        self.diagram.ForcedPublish(self.context)


def _plant_with(
    model: ModelConfig | list[ModelConfig], time_step: float = 0.0
) -> tuple[DiagramBuilder, MultibodyPlant, SceneGraph, dict[str, ModelInstanceIndex]]:
    """A plant of ``model`` (or of a world's models), each fixed where its file puts it."""
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=time_step)
    models = model if isinstance(model, list) else [model]
    fixed = [dataclasses.replace(m, static=True) for m in models]
    instances = add_described_models(Parser(plant), fixed, gazebo_look=False)
    _add_ground_for_cameras(plant, scene_graph)
    plant.Finalize()
    return builder, plant, scene_graph, instances


def _add_ground_for_cameras(plant: MultibodyPlant, scene_graph: SceneGraph) -> None:
    """Gazebo's ground plane (z = 0) for the sensors to see; Meshcat draws its own grid."""
    from pydrake.geometry import GeometryInstance, HalfSpace, PerceptionProperties, RenderLabel, Rgba

    ground = scene_graph.RegisterAnchoredGeometry(
        plant.get_source_id(), GeometryInstance(RigidTransform(), HalfSpace(), "ground_plane")
    )
    properties = PerceptionProperties()
    properties.AddProperty("phong", "diffuse", Rgba(0.7, 0.7, 0.7, 1.0))
    properties.AddProperty("label", "id", RenderLabel.kDontCare)
    scene_graph.AssignRole(plant.get_source_id(), ground, properties)


def model_info(model: ModelConfig) -> dict[str, Any]:
    """What ``view --json`` lists: links, joints (type, parent, child, axis, limits), frames
    (each with its parent), sensors and plugins, as parsed."""
    _, plant, _, instances = _plant_with(model)
    # The model's instance and its nested SDF models' (``model::nested``), in plant order.
    own = [
        ModelInstanceIndex(i)
        for i in range(plant.num_model_instances())
        if plant.GetModelInstanceName(ModelInstanceIndex(i)).split("::")[0] == model.name
    ]
    # (not the weld that fixes the model's root for the view: it is in no file)
    joints = [plant.get_joint(j) for instance in own for j in plant.GetJointIndices(instance)]
    joints = [j for j in joints if not j.name().startswith("world_welds_to_")]
    frames = [plant.get_frame(f) for instance in own for f in plant.GetFrameIndices(instance)]
    tags = model.gazebo
    return {
        "name": model.name,
        "file": model.file,
        "format": model.format,
        "links": [plant.get_body(b).name() for instance in own for b in plant.GetBodyIndices(instance)],
        "joints": [_joint_info(j, _effort_limits(model)) for j in joints],
        "frames": [
            {"name": f.name(), "body": f.body().name()}
            for f in frames
            if not f.name().startswith("__") and not f.name().endswith(("_parent", "_child"))
        ],
        "sensors": [dataclasses.asdict(s) for s in tags.sensors],
        "plugins": [
            *(
                {"kind": "joint_state_publisher", **dataclasses.asdict(p)}
                for p in tags.joint_state_publishers
            ),
            *(
                {"kind": "joint_pose_trajectory", **dataclasses.asdict(p)}
                for p in tags.joint_pose_trajectories
            ),
            *(
                {"kind": "camera", "sensor": s.name, **dataclasses.asdict(s.ros_camera)}
                for s in tags.sensors
                if s.ros_camera is not None
            ),  # fmt: skip
            *({"kind": "unknown", **dataclasses.asdict(p)} for p in tags.unknown_plugins),
            *([{"kind": "ros_control", **dataclasses.asdict(tags.ros_control)}] if tags.ros_control else []),
        ],
        "materials": [dataclasses.asdict(m) for m in tags.materials],
        "frictions": [dataclasses.asdict(f) for f in tags.frictions],
    }


def _joint_info(joint: Joint, efforts: dict[str, float]) -> dict[str, Any]:
    kind = _URDF_TYPES.get(joint.type_name(), joint.type_name())
    info: dict[str, Any] = {
        "name": joint.name(),
        "type": kind,
        "parent": joint.parent_body().name(),
        "child": joint.child_body().name(),
    }
    if kind == "revolute":
        info["axis"] = [float(a) for a in joint.revolute_axis()]
    elif kind == "prismatic":
        info["axis"] = [float(a) for a in joint.translation_axis()]
    if joint.num_positions() == 1:
        lower, upper = float(joint.position_lower_limits()[0]), float(joint.position_upper_limits()[0])
        if kind == "revolute" and math.isinf(lower) and math.isinf(upper):
            info["type"] = "continuous"
        info["limits"] = {
            "lower": _finite(lower),
            "upper": _finite(upper),
            "velocity": _finite(float(joint.velocity_upper_limits()[0])),
            "effort": efforts.get(joint.name()),
        }
    return info


def _finite(value: float) -> Optional[float]:
    return value if math.isfinite(value) else None


def _effort_limits(model: ModelConfig) -> dict[str, float]:
    """A URDF's ``<limit effort>`` per joint (Drake keeps it only on actuators)."""
    if model.format != "urdf":
        return {}
    import xml.etree.ElementTree as ET

    out = {}
    for joint in ET.fromstring(model.description).findall("joint"):
        limit = joint.find("limit")
        if limit is not None and limit.get("effort") is not None:
            out[joint.get("name", "")] = float(limit.get("effort", "0"))
    return out


class ImagePanel(LeafSystem):
    """A sensor's image on a panel in Meshcat (a textured quad at ``X_WP``), redrawn on
    every publish. Input ``image``: ImageRgba8U, or ImageDepth32F drawn grey in [near, far]."""

    def __init__(
        self, meshcat: Meshcat, path: str, X_WP: RigidTransform, depth: Optional[tuple[float, float]]
    ):
        super().__init__()
        self._meshcat, self._path, self._X_WP, self._depth = meshcat, path, X_WP, depth
        self._folder = Path(tempfile.mkdtemp(prefix="omtp_view_"))
        model = ImageDepth32F() if depth is not None else ImageRgba8U()
        self._input = self.DeclareAbstractInputPort("image", Value(model))
        self.DeclareForcedPublishEvent(self._draw)

    def _draw(self, context: Context) -> None:
        image = self._input.Eval(context)
        pixels = np.asarray(image.data)
        if self._depth is not None:
            near, far = self._depth
            depth = np.nan_to_num(pixels[..., 0], nan=far, posinf=far, neginf=near)
            depth[depth <= 0] = near  # Drake's "too close"
            grey = np.clip((depth - near) / (far - near), 0.0, 1.0)
            pixels = (np.repeat(grey[..., None], 3, axis=2) * 255).astype(np.uint8)
        else:
            pixels = np.ascontiguousarray(pixels[..., :3])
        k = len(list(self._folder.glob("*.gltf")))  # a new file each time: Meshcat caches by name
        path = self._folder / f"panel{k}.gltf"
        path.write_text(panel_gltf(pixels))
        self._meshcat.SetObject(self._path, Mesh(str(path)))
        self._meshcat.SetTransform(self._path, self._X_WP)


def panel_gltf(pixels: np.ndarray) -> str:
    """A self-contained glTF of an upright quad, :data:`PANEL_WIDTH` wide in x and as tall
    (z) as the image's aspect says, facing -y, showing ``pixels`` (H x W x 3, uint8) unlit."""
    import base64
    import io

    from matplotlib.image import imsave

    png = io.BytesIO()
    imsave(png, pixels, format="png")
    h, w = pixels.shape[:2]
    half_w, half_h = PANEL_WIDTH / 2, PANEL_WIDTH * h / w / 2
    # glTF is y-up: the quad lies in its x-y plane, turned upright (about x) by the node.
    corners = np.array(
        [[-half_w, -half_h, 0], [half_w, -half_h, 0], [half_w, half_h, 0], [-half_w, half_h, 0]]
    )
    uv = np.array([[0, 1], [1, 1], [1, 0], [0, 0]])
    blob = corners.astype(np.float32).tobytes() + uv.astype(np.float32).tobytes()
    blob += np.array([0, 1, 2, 0, 2, 3], dtype=np.uint16).tobytes()
    png_uri = "data:image/png;base64," + base64.b64encode(png.getvalue()).decode()
    blob_uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}
        ],
        "materials": [
            {
                "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                "emissiveTexture": {"index": 0},
                "emissiveFactor": [1, 1, 1],
                "doubleSided": True,
            }
        ],
        "textures": [{"source": 0}],
        "images": [{"uri": png_uri}],
        "buffers": [{"byteLength": len(blob), "uri": blob_uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12},
        ],
        "accessors": [
            {
                "bufferView": 0,
                "componentType": 5126,
                "count": 4,
                "type": "VEC3",
                "min": [-half_w, -half_h, 0.0],
                "max": [half_w, half_h, 0.0],
            },
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],  # fmt: skip
    }
    return json.dumps(gltf)


def build_model_view(
    model: ModelConfig | list[ModelConfig], meshcat: Meshcat, positions: Optional[dict[str, float]] = None
) -> ModelView:
    """``model`` (or a world's models) in ``meshcat`` with a slider per movable joint,
    starting at ``positions`` (joint name -> position; the rest at 0, or their limit nearest 0)."""
    builder, plant, scene_graph, instances = _plant_with(model)
    models = model if isinstance(model, list) else [model]
    MeshcatVisualizer.AddToBuilder(
        builder, scene_graph, meshcat, MeshcatVisualizerParams(role=Role.kIllustration)
    )
    cameras: dict[str, DepthCamera] = {}
    sensors = [(m, sensor) for m in models for sensor in m.gazebo.cameras()]
    for key, (owner, sensor) in enumerate(sensors):
        instance = instances[owner.name]
        camera = add_depth_camera(builder, plant, scene_graph, instance, owner.name, sensor, seed=0, key=key,
                                  sampled=False)  # fmt: skip
        show_point_cloud(builder, meshcat, camera)
        cameras[sensor.name] = camera
    q0 = _initial_positions(plant, list(instances.values()), positions or {})
    _aim(meshcat, plant, q0)
    for row, camera in enumerate(cameras.values()):
        _add_panels(builder, meshcat, plant, q0, camera, row)
    sliders = builder.AddSystem(JointSliders(meshcat, plant, initial_value=q0))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant.SetPositions(plant.GetMyMutableContextFromRoot(context), q0)
    first = models[0]
    return ModelView(first, meshcat, diagram, context, plant, instances[first.name], sliders, cameras)


def _initial_positions(
    plant: MultibodyPlant, instances: list[ModelInstanceIndex], positions: dict[str, float]
) -> np.ndarray:
    q = np.clip(
        np.zeros(plant.num_positions()), plant.GetPositionLowerLimits(), plant.GetPositionUpperLimits()
    )
    movable = {}
    for index in (j for instance in instances for j in plant.GetJointIndices(instance)):
        joint = plant.get_joint(index)
        if joint.num_positions() == 1:
            movable[joint.name()] = joint
    for name, value in positions.items():
        if name not in movable:
            raise UnknownNameError("movable joint", name, movable)
        joint = movable[name]
        low, high = joint.position_lower_limits()[0], joint.position_upper_limits()[0]
        if not low <= value <= high:
            raise ConfigError(f"joint {name!r}: position {value} is outside its limits [{low}, {high}]")
        q[joint.position_start()] = value
    return q


def _body_origins(plant: MultibodyPlant, q: np.ndarray) -> np.ndarray:
    """The origins of the plant's bodies (but the world) at ``q``, one row each."""
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, q)
    bodies = [plant.get_body(BodyIndex(b)) for b in range(1, plant.num_bodies())]
    return np.array([plant.EvalBodyPoseInWorld(context, body).translation() for body in bodies])


def _aim(meshcat: Meshcat, plant: MultibodyPlant, q: np.ndarray) -> None:
    """Meshcat's camera at the model from the front left, above (the panels face it)."""
    origins = _body_origins(plant, q)
    centre = (origins.min(axis=0) + origins.max(axis=0)) / 2
    size = max(float(np.ptp(origins, axis=0).max()), 0.5)
    meshcat.SetCameraPose(
        list(centre + [0.3 * size, -2.2 * size, 1.4 * size]), list(centre + [0, 0, 0.3 * size])
    )


def _add_panels(
    builder: DiagramBuilder,
    meshcat: Meshcat,
    plant: MultibodyPlant,
    q: np.ndarray,
    camera: DepthCamera,
    row: int,
) -> None:
    """The colour and (depth sensors) depth panels of ``camera``, side by side above the model."""
    origins = _body_origins(plant, q)
    top = origins.max(axis=0)[2] + 0.6 + row * PANEL_WIDTH
    centre_x = (origins.min(axis=0)[0] + origins.max(axis=0)[0]) / 2
    name = camera.config.name
    panels: list[tuple[str, Any, Optional[tuple[float, float]]]] = [("color", camera.color_image, None)]
    if camera.config.type == "depth" and camera.config.camera is not None:
        panels.append(
            ("depth", camera.depth_image, (camera.config.camera.near, min(camera.config.camera.far, 10.0)))
        )
    for k, (kind, port, depth) in enumerate(panels):
        x = centre_x + (k - (len(panels) - 1) / 2) * (PANEL_WIDTH + 0.05)
        panel = builder.AddNamedSystem(
            f"{name}.{kind}_panel",
            ImagePanel(
                meshcat, f"/images/{name}/{kind}", RigidTransform(RotationMatrix(), [x, 0.0, top]), depth
            ),
        )
        builder.Connect(port, panel.get_input_port())


def screenshot_view(view: ModelView, png: str | Path) -> Path:
    """A PNG of the view as it is now (headless chromium on Meshcat's standalone page)."""
    from omtp_drake.viz.browser import screenshot

    view.publish()
    with tempfile.TemporaryDirectory(prefix="omtp_view_") as folder:
        html = Path(folder) / "view.html"
        html.write_text(view.meshcat.StaticHtml())
        return screenshot(html, png)


def run_view(view: ModelView, timeout: float) -> None:
    """Redraws the view whenever a slider moves, until Meshcat's Stop button or
    ``timeout`` wall seconds (inf: until stopped or interrupted)."""
    view.publish()
    view.sliders.Run(view.diagram, None if math.isinf(timeout) else timeout)


def save_sensor_images(view: ModelView, folder: str | Path) -> list[Path]:
    """Each camera sensor's images as the view shows them now: ``<sensor>_color.png``,
    ``<sensor>_depth.png`` (depths as grey, 0 black to the 95th percentile white) and, for a depth
    sensor, ``<sensor>_points.ply`` (its point cloud in its optical frame, with colours)."""
    from matplotlib.image import imsave

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []

    def value(port: Any) -> Any:
        return port.Eval(port.get_system().GetMyContextFromRoot(view.context))

    for name, camera in view.cameras.items():
        color = np.asarray(value(camera.color_image).data)[..., :3]
        written.append(folder / f"{name}_color.png")
        imsave(written[-1], np.ascontiguousarray(color))
        depth = np.asarray(value(camera.depth_image).data)[..., 0]
        finite = np.isfinite(depth) & (depth > 0)
        far = float(np.percentile(depth[finite], 95)) if finite.any() else 1.0
        written.append(folder / f"{name}_depth.png")
        imsave(written[-1], np.where(finite, depth, far), cmap="gray", vmin=0.0, vmax=far)
        if camera.point_cloud is not None:
            cloud = value(camera.point_cloud)
            written.append(folder / f"{name}_points.ply")
            _write_ply(written[-1], cloud.xyzs().T, cloud.rgbs().T)
    return written


def _write_ply(path: Path, xyz: np.ndarray, rgb: np.ndarray) -> None:
    """An ASCII PLY of the finite points with their colours."""
    keep = np.isfinite(xyz).all(axis=1)
    header = (
        f"ply\nformat ascii 1.0\nelement vertex {int(keep.sum())}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
    )
    rows = [f"{x:.4f} {y:.4f} {z:.4f} {r} {g} {b}" for (x, y, z), (r, g, b) in zip(xyz[keep], rgb[keep])]
    path.write_text(header + "\n".join(rows) + "\n")
