"""Occlusion in the logical camera: hidden models are not reported, each reported model
carries the visible share of its image, checked against an independent ray-box oracle.

One cell serves every scene (built once): two parts stacked under camera 2, a part
half behind bin 1's wall seen by a horizontal test camera, and a part in the open
on the belt under camera 1.
"""

import math
from dataclasses import replace

import numpy as np
import pytest
import yaml
from pydrake.math import RigidTransform

from omtp_drake.assets import model_dimensions
from omtp_drake.errors import ConfigError, ScenarioError
from omtp_drake.scenario import LogicalCameraConfig, PartConfig, load_scenario, scenario_from_dict
from omtp_drake.sim.runtime import FactoryRuntime

SIZE = 0.2  # the parts' edge (m)
CORNER = 0.001  # radius of a part's corner spheres: it rests this far above its support
SIDE_CAMERA = LogicalCameraConfig(
    name="side_camera", xyz=[-9.2, -2.05, 0.3], rpy=[0.0, 0.0, 0.0],  # looks along world +x
    near=0.1, far=3.0, horizontal_fov=0.8, aspect_ratio=1.5, occlusion=True)
# Behind bin 1 (x in [-8.2, -7.8], y in [-2.4, -2.0]) as seen from the side camera:
# its outer wall's near edge hides y < about -1.97 at the part's distance.
BEHIND_WALL = [-7.55, -1.97, SIZE / 2 + CORNER]


@pytest.fixture(scope="module")
def cell() -> FactoryRuntime:
    scenario = load_scenario("omtp_factory")
    scenario.parts = [
        # A stack right under camera 2 (at (-8.3, -1.23), looking down).
        PartConfig(name="object_1", xyz=[-8.3, -1.23, SIZE / 2 + CORNER]),
        PartConfig(name="object_2", xyz=[-8.3, -1.23, 1.5 * SIZE + 3 * CORNER]),
        PartConfig(name="object_3", xyz=BEHIND_WALL),
        # In the open, on the belt under camera 1 (lecture 6, assignment 1).
        PartConfig(name="object_4", xyz=[1.2, 1.8, 0.92 + SIZE / 2 + CORNER]),
    ]
    camera_2 = next(c for c in scenario.cameras if c.name == "logical_camera_2")
    scenario.cameras = [
        replace(c, occlusion=True) for c in scenario.cameras
    ] + [
        replace(camera_2, name="camera_2_all", occlusion=True, min_visible_fraction=0.0),
        replace(camera_2, name="camera_2_plain"),  # occlusion off
        SIDE_CAMERA,
    ]
    runtime = FactoryRuntime(scenario)
    runtime.advance_to(0.5)
    runtime.simulator.AdvancePendingEvents()  # the samples due at 0.5 s
    return runtime


def _fractions(runtime: FactoryRuntime, camera: str) -> dict[str, float]:
    image = runtime.camera_image(camera)
    assert image.time == pytest.approx(0.5)
    return {m.name: m.visible_fraction for m in image.models}


def test_part_under_another_is_hidden_from_above(cell):
    everything = _fractions(cell, "camera_2_all")  # min_visible_fraction 0: all with fractions
    assert everything["object_1"] < 0.05
    assert everything["object_2"] > 0.95
    assert set(_fractions(cell, "logical_camera_2")) == {"object_2"}
    plain = cell.camera_image("camera_2_plain")
    without = {m.name: m.visible_fraction for m in plain.models}
    assert {"object_1", "object_2"} <= set(without) and set(without.values()) == {1.0}
    # Where a part is reported, it is reported alike with and without occlusion.
    hidden = {m.name: m for m in cell.camera_image("logical_camera_2").models}
    shown = {m.name: m for m in plain.models}
    assert np.array_equal(hidden["object_2"].X_CM.GetAsMatrix4(), shown["object_2"].X_CM.GetAsMatrix4())


def test_part_in_the_open_is_fully_visible(cell):
    assert _fractions(cell, "logical_camera_1") == {"object_4": pytest.approx(1.0, abs=0.05)}


def _slab_hits(origin: np.ndarray, targets: np.ndarray, boxes: list[tuple[RigidTransform, np.ndarray]]
               ) -> np.ndarray:
    """Which segments origin -> target (n, 3) cross one of the boxes (pose in world, half size)."""
    blocked = np.zeros(len(targets), bool)
    for X_WB, half in boxes:
        X_BW = X_WB.inverse()
        o = X_BW @ origin
        d = (X_BW.rotation().matrix() @ (targets - origin).T).T
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (-half - o) / d, (half - o) / d
        t_near = np.nanmax(np.minimum(t1, t2), axis=1)
        t_far = np.nanmin(np.maximum(t1, t2), axis=1)
        blocked |= (t_near <= t_far) & (t_far > 0) & (t_near < 1 - 1e-9)
    return blocked


def _visible_share_oracle(cell: FactoryRuntime, camera: LogicalCameraConfig, part: str) -> float:
    """The share of the part's image that is unoccluded, by sampling its faces that face
    the camera, each sample weighted by the image-plane area it covers, and testing the
    segment to the camera against bin 1's five boxes (read from models/bin.urdf.xacro)."""
    X_WC = camera.X_PC()
    c = X_WC.translation()
    axis = X_WC.rotation().matrix()[:, 0]  # the camera looks along +Cx
    X_WP = cell.part_pose(part)
    k = 80
    u = (np.arange(k) + 0.5) / k * SIZE - SIZE / 2
    a, b = (g.ravel() for g in np.meshgrid(u, u))
    points, weights = [], []
    for i in range(3):
        for sign in (-1.0, 1.0):
            local = np.zeros((k * k, 3))
            local[:, i] = sign * SIZE / 2
            local[:, (i + 1) % 3], local[:, (i + 2) % 3] = a, b
            p = (X_WP.rotation().matrix() @ local.T).T + X_WP.translation()
            normal = X_WP.rotation().matrix()[:, i] * sign
            to_camera = c - p
            r = np.linalg.norm(to_camera, axis=1)
            cos_theta = to_camera @ normal / r
            if cos_theta.max() <= 0:
                continue  # a face turned away
            depth = (p - c) @ axis
            # Image-plane area at unit depth per unit face area: cos(theta) r / depth^3.
            points.append(p)
            weights.append(np.clip(cos_theta, 0, None) * r / depth**3)
    points, weights = np.concatenate(points), np.concatenate(weights)
    d = model_dimensions("bin.urdf.xacro")
    outer, wall, height, floor_top = d["outer"], d["wall"], d["height"], d["floor_top"]
    X_WBin = cell.bin_pose("bin_1")
    side = (height - floor_top) / 2
    mid = (height + floor_top) / 2
    x_wall, y_wall = np.array([wall / 2, outer / 2, side]), np.array([outer / 2 - wall, wall / 2, side])
    boxes = [
        (X_WBin @ RigidTransform([0, 0, floor_top / 2]), np.array([outer, outer, floor_top]) / 2),
        (X_WBin @ RigidTransform([(outer - wall) / 2, 0, mid]), x_wall),
        (X_WBin @ RigidTransform([-(outer - wall) / 2, 0, mid]), x_wall),
        (X_WBin @ RigidTransform([0, (outer - wall) / 2, mid]), y_wall),
        (X_WBin @ RigidTransform([0, -(outer - wall) / 2, mid]), y_wall),
    ]
    visible = ~_slab_hits(c, points, boxes)
    return float(weights[visible].sum() / weights.sum())


def test_part_half_behind_the_bin_wall(cell):
    truth = _visible_share_oracle(cell, SIDE_CAMERA, "object_3")
    assert 0.3 < truth < 0.7  # the scene is what it claims: about half hidden
    seen = _fractions(cell, "side_camera")
    assert seen["object_3"] == pytest.approx(truth, abs=0.1)
    assert "bin_1" in seen  # the occluder itself is in the open


def test_image_text_and_dict_carry_the_fraction(cell):
    image = cell.camera_image("side_camera")
    assert image.occlusion
    (entry,) = [m for m in image.to_dict()["models"] if m["name"] == "object_3"]
    assert entry["visible_fraction"] == pytest.approx(image.models[[m.name for m in image.models]
                                                                   .index("object_3")].visible_fraction)
    assert "visible_fraction: " in str(image)
    plain = cell.camera_image("camera_2_plain")
    assert not plain.occlusion and "visible_fraction" not in str(plain)
    assert all(m["visible_fraction"] == 1.0 for m in plain.to_dict()["models"])


def test_hidden_parts_get_no_detection_marker(cell):
    from pydrake.geometry import Meshcat

    from omtp_drake.viz.meshcat import DetectionMarkers

    markers = DetectionMarkers(Meshcat(), cell.station).marker_poses(cell)
    top = cell.part_pose("object_2").translation()
    # camera_2_all reports the hidden object_1 (fraction 0): only object_2 is marked.
    (marker,) = markers["camera_2_all"]
    assert np.allclose(marker.translation()[:2], top[:2], atol=1e-3)
    assert len(markers["logical_camera_2"]) == 1 and len(markers["camera_2_plain"]) == 2


def test_occlusion_needs_no_renderer(cell):
    assert cell.station.scene_graph.RendererCount() == 0


def test_off_by_default_in_every_scenario():
    from omtp_drake.scenario import scenario_names

    for name in scenario_names():
        for camera in load_scenario(name).cameras:
            assert (camera.occlusion, camera.rgbd) == (False, False), (name, camera.name)


def test_scenario_keys_and_their_checks(tmp_path):
    raw = yaml.safe_load("""
base: lecture6_assignment1
cameras:
  - {name: logical_camera_1, occlusion: true, min_visible_fraction: 0.2, rgbd: true, rgbd_width: 96}
""")
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(raw))
    camera = load_scenario(path).cameras[0]
    assert (camera.occlusion, camera.min_visible_fraction, camera.rgbd, camera.rgbd_width) == \
        (True, 0.2, True, 96)
    assert camera.rgbd_height() == 64  # 96 / 1.5
    for key, value in [("min_visible_fraction", 1.5), ("min_visible_fraction", -0.1),
                       ("min_visible_fraction", math.nan), ("rgbd_width", 8), ("rgbd_width", 10000)]:
        with pytest.raises(ConfigError, match=f"{key}={value!r} is invalid; valid:"):
            replace(camera, **{key: value}).validate()
    with pytest.raises(ScenarioError, match=r"cameras\[c\]\.occlusion must be true or false, got 'yes'"):
        scenario_from_dict({"cameras": [{"name": "c", "occlusion": "yes"}]})


def _surface_samples(shape, rng: np.random.Generator, n: int = 40000) -> np.ndarray:
    """Points on the surface of a primitive, in its frame."""
    from pydrake.geometry import Box, Capsule, Cylinder, Ellipsoid, Sphere

    unit = rng.normal(size=(n, 3))
    unit /= np.linalg.norm(unit, axis=1, keepdims=True)
    if isinstance(shape, Sphere):
        return unit * shape.radius()
    if isinstance(shape, Ellipsoid):
        return unit * [shape.a(), shape.b(), shape.c()]
    if isinstance(shape, Box):
        half = np.array([shape.width(), shape.depth(), shape.height()]) / 2
        return unit / np.abs(unit).max(axis=1, keepdims=True) * half
    angle = rng.uniform(0, 2 * np.pi, n)
    rim = np.c_[np.cos(angle), np.sin(angle), np.zeros(n)] * shape.radius()
    if isinstance(shape, Cylinder):
        return rim + np.c_[np.zeros((n, 2)), rng.choice([-1, 1], n) * shape.length() / 2]
    assert isinstance(shape, Capsule)
    ends = unit * shape.radius() + np.c_[np.zeros((n, 2)), np.sign(unit[:, 2]) * shape.length() / 2]
    return np.concatenate([ends, rim + np.c_[np.zeros((n, 2)), rng.uniform(-1, 1, n) * shape.length() / 2]])


def test_each_shape_becomes_a_tight_polytope(tmp_path):
    """The slabs of every shape hold all of it and touch it (the 26-DOP's faces are
    supporting planes); a mesh's slabs are those of its vertices."""
    from pydrake.geometry import Box, Capsule, Convex, Cylinder, Ellipsoid, HalfSpace, SceneGraph, Sphere
    from pydrake.multibody.plant import MultibodyPlant

    from omtp_drake.cell.kdop import slabs_in_geometry_frame

    vertices = np.array([[0.3, 0, 0], [-0.1, 0, 0], [0, 0.2, 0], [0, -0.2, 0], [0, 0, 0.1],
                         [0.05, 0.05, -0.25]])
    mesh = tmp_path / "blob.obj"
    mesh.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in vertices)
                    + "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n")
    shapes = [Sphere(0.1), Cylinder(0.1, 0.3), Capsule(0.05, 0.2), Ellipsoid(0.1, 0.2, 0.3),
              Box(0.1, 0.2, 0.3), Convex(str(mesh)), HalfSpace()]
    scene_graph = SceneGraph()
    plant = MultibodyPlant(0.0)
    plant.RegisterAsSourceForSceneGraph(scene_graph)
    ids = [plant.RegisterVisualGeometry(plant.world_body(), RigidTransform(), shape, f"s{i}",
                                        [1, 1, 1, 1]) for i, shape in enumerate(shapes)]
    plant.Finalize()
    inspector = scene_graph.model_inspector()
    rng = np.random.default_rng(3)
    for shape, geometry_id in zip(shapes, ids):
        n, d_plus, d_minus = slabs_in_geometry_frame(inspector, geometry_id)
        assert np.allclose(np.linalg.norm(n, axis=1), 1)
        if isinstance(shape, HalfSpace):
            assert np.allclose(n, [[0, 0, 1]]) and d_plus[0] == 0 and np.isinf(d_minus[0])
            continue
        points = vertices if isinstance(shape, Convex) else _surface_samples(shape, rng)
        along = points @ n.T
        assert (along <= d_plus + 1e-9).all() and (-along <= d_minus + 1e-9).all(), shape
        tolerance = 1e-9 if isinstance(shape, (Convex, Box)) else 2e-3
        assert np.allclose(along.max(axis=0), d_plus, atol=tolerance), shape
        assert np.allclose(-along.min(axis=0), d_minus, atol=tolerance), shape
