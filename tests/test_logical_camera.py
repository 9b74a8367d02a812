"""Tests of omtp_drake.cell.logical_camera on small hand-built plants."""

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
import pytest
from pydrake.common.yaml import yaml_load_typed
from pydrake.geometry import Box, Convex, HalfSpace, ProximityProperties, Sphere
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph, MultibodyPlant
from pydrake.multibody.tree import FixedOffsetFrame, Frame, RigidBody, SpatialInertia
from pydrake.solvers import MathematicalProgram, Solve
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import Context, Diagram, DiagramBuilder

from omtp_drake.cell.logical_camera import (
    DetectedModel,
    LogicalCamera,
    LogicalCameraImage,
    X_CameraOptical,
    add_logical_camera,
    model_type,
)
from omtp_drake.errors import ConfigError
from omtp_drake.scenario import LogicalCameraConfig

# Frustum of the defaults: near 0.2, far 1.0, fov 1.1, aspect 1.5.
NEAR, FAR = 0.2, 1.0
TY = math.tan(1.1 / 2)
TZ = TY / 1.5
EPS = 0.005  # "just inside / just outside" margin
H = 0.05  # half-size of the 0.1 test cubes
# A pose of the camera in the world that exercises every rotation axis.
X_WC = RigidTransform(RollPitchYaw(0.3, -0.4, 2.0), [0.4, -0.7, 1.3])
CUBES = ["object_0", "object_1", "object_2", "object_3", "bin_1", "conveyor"]
# Boxes of varied sizes for the comparison with an independent oracle.
ODD_SIZES = [(0.06 + 0.02 * (i % 4), 0.1 + 0.05 * (i % 3), 0.04 + 0.03 * (i % 5))
             for i in range(24)]


def _inertia() -> SpatialInertia:
    return SpatialInertia.SolidBoxWithMass(1.0, 0.1, 0.1, 0.1)


def _add_box_model(plant: MultibodyPlant, name: str, size: tuple[float, float, float],
                   *, collision: bool = True) -> RigidBody:
    instance = plant.AddModelInstance(name)
    body = plant.AddRigidBody("base", instance, _inertia())
    if collision:
        plant.RegisterCollisionGeometry(body, RigidTransform(), Box(*size), "collision",
                                        ProximityProperties())
    else:
        plant.RegisterVisualGeometry(body, RigidTransform(), Box(*size), "visual", [1, 1, 1, 1])
    return body


@dataclass
class World:
    """One diagram: free boxes, a few special models and several cameras on one frame."""

    diagram: Diagram
    plant: MultibodyPlant
    frame: Frame
    cameras: dict[str, LogicalCamera]
    bodies: dict[str, RigidBody]

    def new_context(self) -> Context:
        """A context with every free body out of view (behind the camera)."""
        root = self.diagram.CreateDefaultContext()
        plant_context = self.plant.GetMyMutableContextFromRoot(root)
        for i, body in enumerate(self.bodies.values()):
            self.plant.SetFreeBodyPose(
                plant_context, body, X_WC @ RigidTransform([-5.0 - i, 0.0, 0.0]))
        return root

    def place(self, root: Context, name: str, X_CB: RigidTransform) -> None:
        """Puts the body of model ``name`` at X_CB in the camera frame."""
        self.plant.SetFreeBodyPose(self.plant.GetMyMutableContextFromRoot(root),
                                   self.bodies[name], X_WC @ X_CB)

    def capture(self, root: Context, camera: str = "cam", time: float = 0.0
                ) -> LogicalCameraImage:
        """Forces one update of a camera at ``time`` and returns its image."""
        root.SetTime(time)
        system = self.cameras[camera]
        context = system.GetMyMutableContextFromRoot(root)
        system.ExecuteForcedEvents(context)
        return system.get_output_port().Eval(context)

    def seen(self, root: Context, camera: str = "cam") -> list[str]:
        return [m.name for m in self.capture(root, camera).models]


def _build_world(tmp_dir: Path, *, seed: int = 0, noise_seed: Optional[int] = None) -> World:
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    bodies = {name: _add_box_model(plant, name, (2 * H, 2 * H, 2 * H), collision=(i % 2 == 0))
              for i, name in enumerate(CUBES)}
    bodies["big_1"] = _add_box_model(plant, "big_1", (0.4, 0.4, 0.4))
    for i, size in enumerate(ODD_SIZES):
        bodies[f"odd_{i}"] = _add_box_model(plant, f"odd_{i}", size)

    # Two bodies: the model's origin (first body) has no geometry and its
    # second body carries a 0.1 cube 0.5 m away along the first body's +y.
    instance = plant.AddModelInstance("arm_1")
    bodies["arm_1"] = plant.AddRigidBody("root", instance, _inertia())
    tip = plant.AddRigidBody("tip", instance, _inertia())
    plant.RegisterCollisionGeometry(tip, RigidTransform(), Box(0.1, 0.1, 0.1), "c",
                                    ProximityProperties())
    plant.WeldFrames(bodies["arm_1"].body_frame(), tip.body_frame(), RigidTransform([0, 0.5, 0]))

    # A mesh whose vertices span [0.5, 0.6] x [0, 0.1] x [0, 0.1] in its body frame.
    obj = tmp_dir / "cube.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x in (0.5, 0.6) for y in (0, 0.1)
                           for z in (0, 0.1)) + "f 1 2 4\nf 1 4 3\nf 5 7 8\nf 5 8 6\n"
                   + "f 1 5 6\nf 1 6 2\nf 3 4 8\nf 3 8 7\nf 1 3 7\nf 1 7 5\nf 2 6 8\nf 2 8 4\n")
    mesh = plant.AddRigidBody("base", plant.AddModelInstance("mesh_1"), _inertia())
    plant.RegisterCollisionGeometry(mesh, RigidTransform(), Convex(str(obj)), "c",
                                    ProximityProperties())
    bodies["mesh_1"] = mesh

    # Welded in view: a floor (HalfSpace + a box) and geometry of the world itself.
    floor = plant.AddRigidBody("base", plant.AddModelInstance("floor"), _inertia())
    X_WF = X_WC @ RigidTransform(RollPitchYaw(0, math.pi / 2, 0), [0.6, 0, 0])
    plant.WeldFrames(plant.world_frame(), floor.body_frame(), X_WF)
    # Illustration only: a HalfSpace on a non-world body in the proximity engine
    # crashes Drake 1.51 with >= 16 dynamic geometries (drake#19263).
    plant.RegisterVisualGeometry(floor, RigidTransform(), HalfSpace(), "ground", [1, 1, 1, 1])
    plant.RegisterVisualGeometry(floor, RigidTransform(), Box(1, 1, 0.01), "tile", [1, 1, 1, 1])
    plant.RegisterVisualGeometry(plant.world_body(), X_WC @ RigidTransform([0.6, 0, 0]),
                                 Sphere(0.1), "world_ball", [1, 1, 1, 1])

    # The camera's own model: a 0.5 cube around the camera frame (it overlaps the near plane).
    own = plant.AddModelInstance("logical_camera_1")
    housing = plant.AddRigidBody("housing", own, _inertia())
    plant.WeldFrames(plant.world_frame(), housing.body_frame(), X_WC)
    plant.RegisterVisualGeometry(housing, RigidTransform(), Box(0.5, 0.5, 0.5), "v", [1, 1, 1, 1])
    frame = plant.AddFrame(FixedOffsetFrame("logical_camera_1_frame", housing.body_frame(),
                                            RigidTransform()))
    plant.Finalize()

    configs = {
        "cam": LogicalCameraConfig(name="cam"),
        "cam_with_own": LogicalCameraConfig(name="cam_with_own"),
        "typed": LogicalCameraConfig(name="typed", known_types=["object", "conveyor"]),
        "named": LogicalCameraConfig(name="named", known_names=["object_3", "bin_1"]),
        "either": LogicalCameraConfig(name="either", known_types=["object"], known_names=["conveyor"]),
        "anonymous": LogicalCameraConfig(name="anonymous", anonymize=True),
        "noisy": LogicalCameraConfig(name="noisy", position_noise_sigma=0.001,
                                     orientation_noise_sigma=0.01, seed=noise_seed),
    }
    cameras = {name: add_logical_camera(builder, plant, scene_graph, frame, config,
                                        exclude=[] if name == "cam_with_own" else [own],
                                        seed=seed)
               for name, config in configs.items()}
    return World(builder.Build(), plant, frame, cameras, bodies)


@pytest.fixture(scope="module")
def world(tmp_path_factory: pytest.TempPathFactory) -> World:
    return _build_world(tmp_path_factory.mktemp("meshes"))


# ----------------------------------------------------------------------------
# Configuration


def test_config_defaults_and_yaml() -> None:
    config = LogicalCameraConfig()
    config.validate()
    assert (config.near, config.far, config.horizontal_fov, config.aspect_ratio) == \
        (0.2, 1.0, 1.1, 1.5)
    loaded = yaml_load_typed(schema=LogicalCameraConfig, data="""
name: logical_camera_2
parent: world
xyz: [-8.3, -1.23, 1.8]
rpy: [0, 1.5708, 0]
near: 0.1
far: 1.8
horizontal_fov: 0.65
aspect_ratio: 1.77777
update_rate_hz: 10
position_noise_sigma: 0.001
orientation_noise_sigma: 0.01
known_types: [object]
known_names: []
anonymize: true
seed: 3
""")
    loaded.validate()
    assert loaded.xyz == [-8.3, -1.23, 1.8] and loaded.known_types == ["object"]
    assert loaded.seed == 3 and loaded.anonymize
    assert np.allclose(loaded.X_PC().translation(), [-8.3, -1.23, 1.8])


@pytest.mark.parametrize("key, value", [
    ("name", ""),
    ("near", 0.0), ("near", -0.1), ("near", math.nan),
    ("far", 0.2), ("far", 0.1), ("far", math.inf),
    ("horizontal_fov", 0.0), ("horizontal_fov", math.pi), ("horizontal_fov", -1.0),
    ("aspect_ratio", 0.0), ("aspect_ratio", -1.5),
    ("position_noise_sigma", -0.001), ("orientation_noise_sigma", -0.01),
    ("xyz", [0.0, 0.0]), ("rpy", [0.0, 0.0, 0.0, 0.0]), ("xyz", [0.0, math.nan, 0.0]),
    ("seed", -1),
])
def test_invalid_config_names_field_and_value(key: str, value: object) -> None:
    config = LogicalCameraConfig(**{key: value})
    with pytest.raises(ConfigError) as error:
        config.validate()
    assert f"{key}={value!r}" in str(error.value)
    assert "valid:" in str(error.value)  # the valid range is part of the message
    # The factory validates first: nothing is added to the builder.
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    plant.Finalize()
    count = len(builder.GetSystems())
    with pytest.raises(ConfigError):
        add_logical_camera(builder, plant, scene_graph, plant.world_frame(), config)
    assert len(builder.GetSystems()) == count


@pytest.mark.parametrize("value", [0.0, -10.0, math.nan, 5000.0])
def test_invalid_update_rate_names_camera_range_and_value(value: float) -> None:
    config = LogicalCameraConfig(name="cam", update_rate_hz=value)
    with pytest.raises(ConfigError) as error:
        config.validate()
    assert str(error.value) == f"logical camera 'cam': update_rate_hz must be in (0, 1000] Hz, got {value}"


def test_invalid_constructor_arguments() -> None:
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    with pytest.raises(ConfigError, match="finalized"):
        LogicalCamera(plant, scene_graph.model_inspector(), plant.world_frame(),
                      LogicalCameraConfig())
    plant.Finalize()
    with pytest.raises(ConfigError, match="seed=-2"):
        add_logical_camera(builder, plant, scene_graph, plant.world_frame(),
                           LogicalCameraConfig(), seed=-2)


def test_model_type() -> None:
    assert model_type("object_3") == "object"
    assert model_type("bin_1") == "bin"
    assert model_type("conveyor") == "conveyor"
    assert model_type("logical_camera_12") == "logical_camera"
    assert model_type("ur10") == "ur10"


def test_optical_frame() -> None:
    R_CO = X_CameraOptical().rotation().matrix()
    assert np.allclose(R_CO[:, 2], [1, 0, 0])  # z_opt = x_cam (forward)
    assert np.allclose(R_CO[:, 0], [0, -1, 0])  # x_opt = -y_cam (right)
    assert np.allclose(R_CO[:, 1], [0, 0, -1])  # y_opt = -z_cam (down)
    assert np.allclose(X_CameraOptical().translation(), 0)


# ----------------------------------------------------------------------------
# Visibility


def _side_touching(normal: np.ndarray, depth: float) -> np.ndarray:
    """Centre of an axis-aligned cube touching a side plane from outside, at ``depth``.

    Side planes go through the apex: n . p = 0, inside n . p <= 0; the cube's
    support along n is h (|nx| + |ny| + |nz|)."""
    unit = normal / np.linalg.norm(normal)
    lateral = np.array([0.0, *normal[1:]]) / np.linalg.norm(normal[1:])  # move sideways
    # p = (depth, s * lateral): n . p = nx depth + s |n_lat| = H sum|n|.
    s = (H * np.abs(normal).sum() - normal[0] * depth) / np.linalg.norm(normal[1:])
    centre = np.array([depth, 0.0, 0.0]) + s * lateral
    assert math.isclose(unit @ centre, H * np.abs(unit).sum(), abs_tol=1e-12)
    return centre


SIDE_NORMALS = {"+y": np.array([-TY, 1, 0]), "-y": np.array([-TY, -1, 0]),
                "+z": np.array([-TZ, 0, 1]), "-z": np.array([-TZ, 0, -1])}


@pytest.mark.parametrize("plane", ["near", "far", *SIDE_NORMALS])
@pytest.mark.parametrize("inside", [True, False])
def test_frustum_planes(world: World, plane: str, inside: bool) -> None:
    sign = -1.0 if inside else 1.0  # along the outward normal
    if plane == "near":
        centre = np.array([NEAR - H - sign * EPS, 0.0, 0.0])
    elif plane == "far":
        centre = np.array([FAR + H + sign * EPS, 0.0, 0.0])
    else:
        normal = SIDE_NORMALS[plane]
        centre = _side_touching(normal, 0.6) + sign * EPS * normal / np.linalg.norm(normal)
    root = world.new_context()
    world.place(root, "object_0", RigidTransform(centre))
    assert world.seen(root) == (["object_0"] if inside else [])


def test_partial_overlap_and_counts(world: World) -> None:
    root = world.new_context()
    # Centre beyond the far plane, 5 cm of the 0.4 cube inside.
    world.place(root, "big_1", RigidTransform([FAR + 0.15, 0, 0]))
    # Centre outside the +y side, a corner inside.
    world.place(root, "object_1", RigidTransform(
        _side_touching(SIDE_NORMALS["+y"], 0.5) - 0.02 * np.array([0, 1, 0])))
    world.place(root, "object_2", RigidTransform([0.5, 0.0, 0.0]))  # fully inside
    world.place(root, "object_3", RigidTransform([1.5, 0.0, 0.0]))  # beyond far
    world.place(root, "bin_1", RigidTransform([0.5, 2.0, 0.0]))  # far to the side
    assert world.seen(root) == ["object_1", "object_2", "big_1"]  # model-instance order


def test_rotated_box_corner_pokes_in(world: World) -> None:
    # Centre 6.5 cm before the near plane: axis-aligned, the cube stays 1.5 cm out;
    # turned 45 deg about Cz its vertical edge reaches h sqrt(2) = 7.07 cm, 5.7 mm in.
    root = world.new_context()
    world.place(root, "object_0", RigidTransform([NEAR - 0.065, 0, 0]))
    assert world.seen(root) == []
    world.place(root, "object_0", RigidTransform(RollPitchYaw(0, 0, math.pi / 4),
                                                 [NEAR - 0.065, 0, 0]))
    assert world.seen(root) == ["object_0"]


def test_box_behind_camera(world: World) -> None:
    root = world.new_context()
    world.place(root, "object_0", RigidTransform([-0.5, 0, 0]))
    world.place(root, "big_1", RigidTransform([-0.6, 0, 0]))  # mirror image of a seen pose
    assert world.seen(root) == []


def test_own_model_floor_and_world_never_reported(world: World) -> None:
    root = world.new_context()
    assert world.seen(root) == []  # floor (HalfSpace + tile) and world ball are in view
    assert world.seen(root, "cam_with_own") == ["logical_camera_1"]


def test_body_other_than_origin_makes_model_seen(world: World) -> None:
    root = world.new_context()
    # The origin body is out of view (0.5 m to the side), its second body at (0.6, 0, 0).
    X_CM = RigidTransform([0.6, -0.5, 0])
    world.place(root, "arm_1", X_CM)
    (model,) = world.capture(root).models
    assert model.name == "arm_1" and model.type == "arm"
    assert np.allclose(model.X_CM.GetAsMatrix4(), X_CM.GetAsMatrix4(), atol=1e-9)
    world.place(root, "arm_1", RigidTransform([0.6, 0.5, 0]))  # tip at 1.0 to the side
    assert world.seen(root) == []


def test_mesh_bounding_box_from_vertices(world: World) -> None:
    root = world.new_context()
    # Vertices x in [0.5, 0.6] of the body frame: body at x = -0.35 puts them at [0.15, 0.25].
    world.place(root, "mesh_1", RigidTransform([-0.35, -0.05, -0.05]))
    assert world.seen(root) == ["mesh_1"]
    world.place(root, "mesh_1", RigidTransform([-0.40 - EPS, -0.05, -0.05]))  # at 0.1 .. 0.195
    assert world.seen(root) == []


def _oracle_overlap(X_CB: RigidTransform, size: tuple[float, float, float]) -> float:
    """The largest margin t such that a point is inside both shapes by t (an LP);
    they overlap iff t >= 0."""
    normals = np.array([[-1, 0, 0], [1, 0, 0], [-TY, 1, 0], [-TY, -1, 0],
                        [-TZ, 0, 1], [-TZ, 0, -1]], float)
    offsets = np.array([-NEAR, FAR, 0, 0, 0, 0])
    axes = X_CB.rotation().matrix().T  # rows: the box axes in C
    half = np.array(size) / 2
    centre = axes @ X_CB.translation()
    # Rows over x = [p, t]: n.p + |n| t <= b,  +-(a.p - a.c) + t <= h,  t <= 1.
    A = np.block([[normals, np.linalg.norm(normals, axis=1)[:, None]],
                  [axes, np.ones((3, 1))],
                  [-axes, np.ones((3, 1))],
                  [np.zeros((1, 3)), np.ones((1, 1))]])
    upper = np.concatenate([offsets, half + centre, half - centre, [1.0]])
    program = MathematicalProgram()
    x = program.NewContinuousVariables(4, "x")
    program.AddLinearConstraint(A, np.full(len(upper), -np.inf), upper, x)
    program.AddLinearCost([0, 0, 0, -1], x)
    result = Solve(program)
    assert result.is_success()
    return result.GetSolution(x)[3]


def test_matches_independent_oracle(world: World) -> None:
    """Random boxes near the frustum, compared with a linear program."""
    rng = np.random.default_rng(1)
    names = [f"odd_{i}" for i in range(len(ODD_SIZES))]
    checked = {True: 0, False: 0}
    for _ in range(12):
        root = world.new_context()
        expected = []
        for name, size in zip(names, ODD_SIZES):
            rpy = rng.uniform(-math.pi, math.pi, 3)
            position = rng.uniform([-0.1, -0.8, -0.6], [1.2, 0.8, 0.6])
            X_CB = RigidTransform(RollPitchYaw(rpy), position)
            margin = _oracle_overlap(X_CB, size)
            if abs(margin) < 1e-6:
                continue  # touching: either answer is right
            world.place(root, name, X_CB)
            if margin > 0:
                expected.append(name)
            checked[margin > 0] += 1
        assert world.seen(root) == expected
    assert min(checked.values()) > 50


def test_every_stage_of_the_overlap_test_matches_the_oracle(monkeypatch) -> None:
    """Boxes straddling the frustum's faces, edges and corners: each answer equals the
    LP's, and all three stages decide some (centre or face normals; a vertex inside;
    the 21 edge and box axes, with both answers)."""
    from omtp_drake.cell.frustum import FrustumOverlap

    overlap = FrustumOverlap(LogicalCameraConfig(name="c"))
    full_answers: list[bool] = []
    full_test = overlap.not_separated_by_edges_or_box

    def spy(*args):
        answer = full_test(*args)
        full_answers.extend(answer.tolist())
        return answer

    monkeypatch.setattr(overlap, "not_separated_by_edges_or_box", spy)
    rng = np.random.default_rng(7)
    # Points on the frustum's boundary: its 8 corners and the middles of its 12 edges.
    corners = np.array([[d, sy * d * TY, sz * d * TZ] for d in (NEAR, FAR)
                        for sy in (-1, 1) for sz in (-1, 1)])
    edges = [(a + b) / 2 for i, a in enumerate(corners) for b in corners[i + 1:]
             if np.count_nonzero(np.isclose(a, b)) >= 1]
    anchors = np.concatenate([corners, edges])
    poses, sizes, expected = [], [], []
    while len(poses) < 600:
        X_CB = RigidTransform(RollPitchYaw(rng.uniform(-math.pi, math.pi, 3)),
                              anchors[rng.integers(len(anchors))] + rng.normal(0, 0.06, 3))
        size = rng.uniform(0.03, 0.2, 3)
        margin = _oracle_overlap(X_CB, tuple(size))
        if abs(margin) < 1e-6:
            continue  # touching: either answer is right
        poses.append(X_CB)
        sizes.append(size)
        expected.append(margin > 0)
    p_CB = np.array([X.translation() for X in poses])
    R_CB = np.array([X.rotation().matrix() for X in poses])
    answers = overlap.overlaps(p_CB, R_CB, np.array(sizes) / 2)
    assert answers.tolist() == expected
    centre_inside = int((overlap.face_distances(p_CB) <= 0).all(axis=1).sum())
    decided_by_vertex = sum(expected) - sum(full_answers) - centre_inside
    assert decided_by_vertex > 20
    assert full_answers.count(True) > 5 and full_answers.count(False) > 5


def test_course_camera_1_geometry() -> None:
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    config = LogicalCameraConfig(name="logical_camera_1", xyz=[1.2, 1.8, 2.0],
                                 rpy=[0, 1.5708, 0], near=0.2, far=1.0, horizontal_fov=1.1,
                                 aspect_ratio=1.5)
    frame = plant.AddFrame(FixedOffsetFrame("logical_camera_1_frame", plant.world_frame(),
                                            config.X_PC()))
    part = _add_box_model(plant, "object_1", (0.2, 0.2, 0.2))  # bottom on the belt (0.92)
    plant.WeldFrames(plant.world_frame(), part.body_frame(), RigidTransform([1.2, 1.8, 1.02]))
    belt = _add_box_model(plant, "conveyor", (0.6, 10.0, 0.1))  # top at 0.92
    plant.WeldFrames(plant.world_frame(), belt.body_frame(), RigidTransform([1.2, 0.0, 0.87]))
    plant.Finalize()
    camera = add_logical_camera(builder, plant, scene_graph, frame, config)
    simulator = Simulator(builder.Build())
    simulator.Initialize()
    image = camera.get_output_port().Eval(camera.GetMyContextFromRoot(simulator.get_context()))
    assert [m.name for m in image.models] == ["object_1"]
    X_WM = image.X_WC @ image.models[0].X_CM
    assert np.allclose(X_WM.translation(), [1.2, 1.8, 1.02], atol=1e-9)
    assert np.allclose(image.X_WC.translation(), [1.2, 1.8, 2.0])
    # The camera looks down: its +x is the world's -z.
    assert np.allclose(image.X_WC.rotation().matrix()[:, 0], [0, 0, -1], atol=1e-5)


# ----------------------------------------------------------------------------
# Reported values


def test_reported_pose_and_quaternion(world: World) -> None:
    root = world.new_context()
    X_CB = RigidTransform(RollPitchYaw(0.7, -0.2, 2.5), [0.6, 0.1, -0.05])
    world.place(root, "object_3", X_CB)
    image = world.capture(root, time=0.0)
    (model,) = image.models
    plant_context = world.plant.GetMyContextFromRoot(root)
    X_CM = world.plant.CalcRelativeTransform(plant_context, world.frame,
                                             world.bodies["object_3"].body_frame())
    assert np.allclose(model.X_CM.GetAsMatrix4(), X_CM.GetAsMatrix4(), atol=1e-9)
    X_WC_plant = world.plant.CalcRelativeTransform(plant_context, world.plant.world_frame(),
                                                   world.frame)
    assert np.allclose(image.X_WC.GetAsMatrix4(), X_WC_plant.GetAsMatrix4(), atol=1e-12)
    q = X_CM.rotation().ToQuaternion()
    entry = image.to_dict()["models"][0]
    assert entry["name"] == "object_3" and entry["type"] == "object"
    assert np.allclose(entry["pose"]["rotation_xyzw"], [q.x(), q.y(), q.z(), q.w()], atol=1e-9)
    assert np.allclose(entry["pose"]["translation"], X_CM.translation(), atol=1e-9)
    # The quaternion rebuilds the rotation (no swapped components).
    x, y, z, w = entry["pose"]["rotation_xyzw"]
    assert np.allclose(_quaternion_matrix(w, x, y, z), X_CM.rotation().matrix(), atol=1e-9)


def _quaternion_matrix(w: float, x: float, y: float, z: float) -> np.ndarray:
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_to_dict_and_str(world: World) -> None:
    root = world.new_context()
    world.place(root, "bin_1", RigidTransform([0.5, 0, 0]))
    image = world.capture(root, time=0.3)
    data = image.to_dict()
    assert data["time"] == pytest.approx(0.3) and data["camera_name"] == "cam"
    assert set(data["camera_pose"]) == {"translation", "rotation_xyzw"}
    assert data["models"] == [{"name": "bin_1", "type": "bin", "pose": {
        "translation": pytest.approx([0.5, 0, 0]),
        "rotation_xyzw": pytest.approx([0, 0, 0, 1])}, "visible_fraction": 1.0}]
    text = str(image)
    for line in ['camera_name: "cam"', "models:", 'name: "bin_1"', 'type: "bin"',
                 "position:", "orientation:", "w: 1.0"]:
        assert line in text
    assert "models: []" in str(world.capture(world.new_context()))


def test_types_and_filters(world: World) -> None:
    root = world.new_context()
    for i, name in enumerate(["object_3", "bin_1", "conveyor", "object_1"]):
        world.place(root, name, RigidTransform([0.5, -0.15 + 0.1 * i, 0]))
    everything = world.capture(root).models
    assert [(m.name, m.type) for m in everything] == [
        ("object_1", "object"), ("object_3", "object"), ("bin_1", "bin"),
        ("conveyor", "conveyor")]
    assert world.seen(root, "typed") == ["object_1", "object_3", "conveyor"]
    assert world.seen(root, "named") == ["object_3", "bin_1"]
    # Either list, as the course plugin's known_model_types / known_model_names.
    assert world.seen(root, "either") == ["object_1", "object_3", "conveyor"]
    anonymous = world.capture(root, "anonymous").models
    assert [(m.name, m.type) for m in anonymous] == [
        ("", "object"), ("", "object"), ("", "bin"), ("", "conveyor")]
    for plain, anon in zip(everything, anonymous):
        assert np.allclose(plain.X_CM.GetAsMatrix4(), anon.X_CM.GetAsMatrix4())


# ----------------------------------------------------------------------------
# Noise


def _noisy_samples(world: World, count: int) -> np.ndarray:
    """(count, 6): position error and roll-pitch-yaw of the rotation error of object_0."""
    root = world.new_context()
    X_CM = RigidTransform(RollPitchYaw(0.2, 0.3, -0.4), [0.5, 0.05, 0.0])
    world.place(root, "object_0", X_CM)
    rows = []
    for k in range(count):
        (model,) = world.capture(root, "noisy", time=k / 10).models
        R_error = X_CM.rotation().inverse() @ model.X_CM.rotation()  # the draw: R_CM @ R_pert
        rows.append([*(model.X_CM.translation() - X_CM.translation()),
                     *RollPitchYaw(R_error).vector()])
    return np.array(rows)


def test_noise_statistics(world: World) -> None:
    samples = _noisy_samples(world, 2000)
    for column, sigma in zip(samples.T, [0.001] * 3 + [0.01] * 3):
        assert abs(column.mean()) < 4 * sigma / math.sqrt(len(column))
        assert abs(column.std(ddof=1) / sigma - 1) < 0.1
    # The same pose without noise.
    root = world.new_context()
    world.place(root, "object_0", RigidTransform([0.5, 0, 0]))
    for camera in ("cam", "noisy"):
        (model,) = world.capture(root, camera, time=0.7).models
        error = np.linalg.norm(model.X_CM.translation() - [0.5, 0, 0])
        assert (error < 1e-12) == (camera == "cam")


def test_orientation_noise_is_composed_on_the_model_axes(world: World) -> None:
    """ROSLogicalCameraPlugin::AddNoise perturbs the orientation as ``Rot *= pert``: the
    published rotation is R_CM @ R_pert (about the model's own axes), not R_pert @ R_CM.
    The draw at one time is read off an unrotated model, then checked on a rotated one."""
    root = world.new_context()
    p_CM = np.array([0.5, 0.05, 0.0])
    world.place(root, "object_0", RigidTransform(p_CM))
    (model,) = world.capture(root, "noisy", time=0.3).models
    R_pert, dp = model.X_CM.rotation(), model.X_CM.translation() - p_CM  # the draw at 0.3 s
    R_CM = RollPitchYaw(0.2, 0.3, -0.4).ToRotationMatrix()
    world.place(root, "object_0", RigidTransform(R_CM, p_CM))
    (model,) = world.capture(root, "noisy", time=0.3).models
    np.testing.assert_allclose(model.X_CM.rotation().matrix(), (R_CM @ R_pert).matrix(), atol=1e-9)
    np.testing.assert_allclose(model.X_CM.translation(), p_CM + dp, atol=1e-12)
    # The draw is large enough for the two orders to differ.
    assert np.abs((R_pert @ R_CM).matrix() - (R_CM @ R_pert).matrix()).max() > 1e-4


def test_noise_is_a_function_of_seed_and_time(world: World, tmp_path: Path) -> None:
    first = _noisy_samples(world, 5)
    assert np.array_equal(first, _noisy_samples(world, 5))  # no hidden state
    assert not np.allclose(first[0], first[1])  # samples differ
    # A rebuilt world: same scenario seed, same sequence; the camera's own seed wins.
    assert np.array_equal(first, _noisy_samples(_build_world(tmp_path, seed=0), 5))
    assert np.array_equal(first, _noisy_samples(_build_world(tmp_path, seed=9, noise_seed=0), 5))
    other = _noisy_samples(_build_world(tmp_path, seed=1), 5)
    assert not np.any(np.isclose(first, other))


# ----------------------------------------------------------------------------
# Sampling


def test_sample_and_hold() -> None:
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    part = _add_box_model(plant, "object_1", (0.1, 0.1, 0.1))
    plant.WeldFrames(plant.world_frame(), part.body_frame(), RigidTransform([0.5, 0, 0]))
    plant.Finalize()
    camera = add_logical_camera(builder, plant, scene_graph, plant.world_frame(),
                                LogicalCameraConfig(name="cam", update_rate_hz=10.0))
    assert camera.get_name() == "cam"
    simulator = Simulator(builder.Build())
    context = camera.GetMyContextFromRoot(simulator.get_context())
    before = camera.get_output_port().Eval(context)
    assert math.isnan(before.time) and before.models == ()
    simulator.Initialize()
    first = camera.get_output_port().Eval(context)
    assert first.time == 0.0 and [m.name for m in first.models] == ["object_1"]
    assert isinstance(first.models[0], DetectedModel)
    simulator.AdvanceTo(0.05)
    assert camera.get_output_port().Eval(context).time == 0.0
    simulator.AdvanceTo(0.25)
    assert camera.get_output_port().Eval(context).time == pytest.approx(0.2)


def test_image_lives_in_the_state_it_declared() -> None:
    """Issue 10 bug 6: the camera writes its own abstract state, not slot 0. A camera
    class that declares another abstract state first (cooperative inheritance) keeps
    that state untouched and still publishes its images."""
    from pydrake.common.value import AbstractValue
    from pydrake.systems.framework import LeafSystem

    class EarlierState(LeafSystem):
        def __init__(self) -> None:
            super().__init__()
            self.DeclareAbstractState(AbstractValue.Make("untouched"))

    class CameraWithMore(LogicalCamera, EarlierState):
        pass

    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    part = _add_box_model(plant, "object_1", (0.1, 0.1, 0.1))
    plant.WeldFrames(plant.world_frame(), part.body_frame(), RigidTransform([0.5, 0, 0]))
    plant.Finalize()
    camera = builder.AddSystem(CameraWithMore(plant, scene_graph.model_inspector(),
                                              plant.world_frame(), LogicalCameraConfig(name="cam")))
    builder.Connect(plant.get_body_poses_output_port(), camera.get_input_port(0))
    simulator = Simulator(builder.Build())
    simulator.Initialize()
    simulator.AdvanceTo(0.15)
    context = camera.GetMyContextFromRoot(simulator.get_context())
    assert context.get_abstract_state(0).get_value() == "untouched"
    image = camera.get_output_port().Eval(context)
    assert image.time == pytest.approx(0.1) and [m.name for m in image.models] == ["object_1"]


def test_image_shows_the_world_at_its_sample_time_whenever_it_is_read() -> None:
    """The camera stores the body poses of each sample and computes the image only when
    it is read (issue 20): read after the part moved, the image still shows where the
    part was at the sample; the next sample shows the move."""
    from omtp_drake.sim.runtime import FactoryRuntime

    rt = FactoryRuntime("lecture6_assignment1")  # a part on the belt under camera 1
    rt.advance_to(0.25)  # samples at 0, 0.1 and 0.2 (none read yet)
    (name,) = rt.parts_in_world()
    X_WP = rt.part_pose(name)
    plant = rt.station.plant
    moved = RigidTransform(X_WP.rotation(), X_WP.translation() + [0.1, 0.0, 0.0])
    plant.SetFreeBodyPose(plant.GetMyMutableContextFromRoot(rt.context), plant.GetBodyByName(name), moved)
    image = rt.camera_image("logical_camera_1")
    assert image.time == pytest.approx(0.2)
    X_WM = image.X_WC @ next(m.X_CM for m in image.models if m.name == name)
    np.testing.assert_allclose(X_WM.translation(), X_WP.translation(), atol=1e-4)  # not 0.1 m on
    rt.advance_to(0.35)
    later = rt.camera_image("logical_camera_1")
    X_WM = later.X_WC @ next(m.X_CM for m in later.models if m.name == name)
    assert later.time == pytest.approx(0.3)
    assert X_WM.translation()[0] == pytest.approx(moved.translation()[0], abs=0.01)
