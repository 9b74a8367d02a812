"""The URDF tutorial's robot (tests/fixtures/tutorial_ws: a plate, a slider, an arm and a
depth camera, with the tutorial's <gazebo> tags) as the scenario's model entry, in the
station, and its depth camera's images and point cloud."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from pydrake.common.yaml import yaml_dump_typed, yaml_load_typed
from pydrake.systems.analysis import Simulator

from omtp_drake.cell.frames import FrameTree
from omtp_drake.cell.station import build_station
from omtp_drake.errors import ConfigError, MissingPackageError, WorkspaceError
from omtp_drake.scenario import Scenario, model_from_file, model_from_text
from omtp_drake.workspace import Workspace

FIXTURE = Path(__file__).parent / "fixtures" / "tutorial_ws" / "src"
ROBOT = FIXTURE / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
#: Heights of the surfaces the camera sees at the start: the floor and the plate's top.
FLOOR_Z, PLATE_TOP_Z = 0.0, 0.08
PLATE_HALF = (1.0, 0.6)
#: Half the width of the floor slab's top (the cell's floor, 20.1 m; beyond: its side faces).
FLOOR_HALF = 10.05


@pytest.fixture(scope="module")
def robot():
    return model_from_file(ROBOT, Workspace.from_dirs([FIXTURE], environ={}))


@pytest.fixture(scope="module")
def station(robot):
    return build_station(Scenario(name="empty_world", models=[robot]))


def test_gazebo_tags_are_read_into_typed_settings(robot):
    tags = robot.gazebo
    (sensor,) = tags.sensors
    assert (sensor.name, sensor.type, sensor.link, sensor.rate) == (
        "tip_camera",
        "depth",
        "camera_link",
        20.0,
    )
    camera = sensor.camera
    assert (camera.width, camera.height, camera.horizontal_fov) == (640, 480, 1.396)
    assert (camera.near, camera.far, camera.noise_type, camera.noise_stddev) == (
        0.02,
        300.0,
        "gaussian",
        0.007,
    )
    plugin = sensor.ros_camera
    assert (plugin.frame_name, plugin.min_depth, plugin.max_depth) == ("camera_link_optical", 0.05, 100.0)
    (states,) = tags.joint_state_publishers
    assert states.joint_names == ["slider_joint", "arm_joint"] and states.update_rate == 20.0
    (trajectory,) = tags.joint_pose_trajectories
    assert (trajectory.topic, trajectory.update_rate) == ("set_joint_trajectory", 2.0)
    assert {m.link: m.name for m in tags.materials}["arm_link"] == "Gazebo/Orange"
    assert tags.frictions[0].mu1 == 0.8 and not tags.unknown_plugins


def test_a_scenario_with_the_model_survives_yaml(robot):
    scenario = Scenario(name="t", models=[robot])
    again = yaml_load_typed(schema=Scenario, data=yaml_dump_typed(scenario))
    again.validate()
    assert again.models[0].gazebo == robot.gazebo
    assert again.models[0].description == robot.description


def test_every_link_is_a_tf_frame(station):
    names = set(FrameTree(station.plant).names())
    links = {"base_link", "slider_link", "arm_link", "camera_link", "camera_link_optical"}
    assert links <= names
    joints = {
        station.plant.get_joint(j).name(): station.plant.get_joint(j).type_name()
        for j in station.plant.GetJointIndices(station.models["slider_arm"])
    }
    assert joints["slider_joint"] == "prismatic" and joints["arm_joint"] == "revolute"


def test_a_spawn_pose_moves_a_world_fixed_robot(robot):
    moved = dataclasses.replace(robot, xyz=[1.0, 2.0, 0.0], rpy=[0.0, 0.0, math.pi / 2])
    station = build_station(Scenario(name="moved", models=[moved]))
    context = station.create_context()
    X_WB = station.plant.GetFrameByName("base_link").CalcPoseInWorld(
        station.plant.GetMyContextFromRoot(context)
    )
    np.testing.assert_allclose(X_WB.translation(), [1.0, 2.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(X_WB.rotation().matrix()[:, 0], [0.0, 1.0, 0.0], atol=1e-9)


def test_the_depth_camera_sees_the_floor_and_the_plate(station):
    context = station.diagram.CreateDefaultContext()
    station.initialize_context(context)
    Simulator(station.diagram, context).AdvanceTo(0.06)
    color = station.diagram.GetOutputPort("tip_camera.color_image").Eval(context)
    depth = station.diagram.GetOutputPort("tip_camera.depth_image").Eval(context)
    assert (color.width(), color.height(), depth.width(), depth.height()) == (640, 480, 640, 480)
    # Lit as in Gazebo (the sun from above): the floor below the horizon is grey, not black.
    assert np.asarray(color.data)[300:, :, :3].mean() > 60
    cloud = station.diagram.GetOutputPort("tip_camera.point_cloud").Eval(context)
    p_OP = cloud.xyzs()
    seen = np.isfinite(p_OP).all(axis=0)
    assert seen.sum() > 100_000  # the lower half of the image sees the ground
    plant_context = station.plant.GetMyContextFromRoot(context)
    X_WO = station.plant.GetFrameByName("camera_link_optical").CalcPoseInWorld(plant_context)
    p_WP = X_WO.multiply(p_OP[:, seen])
    on_top = (np.abs(p_WP[:2]) < FLOOR_HALF - 0.01).all(axis=0)
    assert on_top.mean() > 0.95
    p_WP = p_WP[:, on_top]  # the rest hit the slab's side faces, at its edge
    assert (np.abs(X_WO.multiply(p_OP[:, seen])[:2, ~on_top]).max(axis=0) > FLOOR_HALF - 0.01).all()
    on_plate = (np.abs(p_WP[0]) <= PLATE_HALF[0] + 0.01) & (np.abs(p_WP[1]) <= PLATE_HALF[1] + 0.01)
    expected_z = np.where(on_plate & (p_WP[2] > 0.04), PLATE_TOP_Z, FLOOR_Z)
    assert np.abs(p_WP[2] - expected_z).max() < 0.01
    assert on_plate.any() and (~on_plate).any()


def test_the_colour_noise_is_seeded(robot):
    images = []
    for seed in (1, 1, 2):
        station = build_station(Scenario(name="s", seed=seed, models=[robot]))
        context = station.diagram.CreateDefaultContext()
        station.initialize_context(context)
        Simulator(station.diagram, context).AdvanceTo(0.01)
        image = station.diagram.GetOutputPort("tip_camera.color_image").Eval(context)
        images.append(np.array(image.data, copy=True))
    assert np.array_equal(images[0], images[1]) and not np.array_equal(images[0], images[2])


def _with_plugin_value(old: str, new: str) -> str:
    text = ROBOT.parent.joinpath("slider_arm.gazebo.xacro").read_text()
    assert old in text
    return text.replace(old, new)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "<update_rate>${camera_rate}</update_rate>",
            "<update_rate>-5</update_rate>",
            "update_rate must be in",
        ),
        (
            "<horizontal_fov>1.396</horizontal_fov>",
            "<horizontal_fov>3.2</horizontal_fov>",
            "horizontal_fov must",
        ),
        ("<width>640</width>", "<width>wide</width>", "'wide' is not a number"),
        ("<min_depth>0.05</min_depth>", "<min_depth>200</min_depth>", "min_depth < max_depth"),
    ],
)
def test_a_plugin_value_out_of_range_is_one_error_naming_the_file(tmp_path, old, new, message):
    package = tmp_path / "src" / "slider_arm_description"
    (package / "urdf").mkdir(parents=True)
    (package / "package.xml").write_text((ROBOT.parents[1] / "package.xml").read_text())
    for name in ("slider_arm.urdf.xacro", "inertia.xacro"):
        (package / "urdf" / name).write_text((ROBOT.parent / name).read_text())
    (package / "urdf" / "slider_arm.gazebo.xacro").write_text(_with_plugin_value(old, new))
    with pytest.raises(ConfigError, match=message) as error:
        model_from_file(
            package / "urdf" / "slider_arm.urdf.xacro", Workspace.from_dirs([tmp_path], environ={})
        )
    assert "slider_arm.urdf.xacro" in str(error.value) and "\n" not in str(error.value)


def test_a_missing_package_names_it_and_the_flag(tmp_path):
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find no_such_pkg)/x.xacro"/><link name="a"/></robot>'
    )
    with pytest.raises(MissingPackageError, match="no_such_pkg.*--workspace"):
        model_from_file(robot, Workspace.from_dirs([], environ={}))


def test_an_sdf_drake_refuses_is_one_error_naming_the_file(tmp_path):
    text = (
        '<sdf version="1.7"><model name="m"><link name="a"/><joint name="j" type="revolute">'
        "<parent>a</parent><child>nowhere</child></joint></model></sdf>"
    )
    model = model_from_text(text, str(tmp_path / "m.sdf"), Workspace.from_dirs([], environ={}))
    with pytest.raises(WorkspaceError, match=r"m\.sdf: Drake's parser refuses it: ") as error:
        build_station(Scenario(name="bad", models=[model]))
    assert "\n" not in str(error.value)


def test_gazebo_material_and_friction_apply_in_the_simulation(station):
    from pydrake.geometry import Role

    inspector = station.scene_graph.model_inspector()

    def geometries(link: str, role: Role) -> list:
        body = station.plant.GetBodyByName(link)
        return inspector.GetGeometries(station.plant.GetBodyFrameIdOrThrow(body.index()), role)

    (arm,) = geometries("arm_link", Role.kIllustration)
    rgba = inspector.GetIllustrationProperties(arm).GetProperty("phong", "diffuse")
    assert (rgba.r(), rgba.g(), rgba.b()) == pytest.approx((1.0, 0.5088, 0.0468))  # Gazebo/Orange
    (plate,) = geometries("base_link", Role.kProximity)
    friction = inspector.GetProximityProperties(plate).GetProperty("material", "coulomb_friction")
    assert (friction.static_friction(), friction.dynamic_friction()) == pytest.approx((0.8, 0.8))


def test_a_robot_file_is_a_scenario_for_the_inspecting_commands(capsys):
    from omtp_drake.cli import main

    assert main(["tf-echo", str(ROBOT), "world", "camera_link_optical", "--json"]) == 0
    import json

    out = json.loads(capsys.readouterr().out)
    # camera_link is 0.8 m along the level arm, 0.11 m above it: x = -1 + 0.4 + 0.8, z = 0.08 + 0.12 + 0.11
    assert out["translation"] == pytest.approx([0.2, 0.0, 0.31], abs=1e-3)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"description": "<robot name='x'><link"}, "not well-formed XML"),
        ({"format": "sdf"}, "format 'sdf', but the description is URDF"),
        ({"name": "has space"}, "model name 'has space' must be"),
        ({"xyz": [0.0, 1.0]}, "xyz needs 3 numbers"),
    ],
)
def test_a_bad_models_entry_is_one_error(robot, change, message):
    with pytest.raises(ConfigError, match=message):
        Scenario(name="bad", models=[dataclasses.replace(robot, **change)]).validate()


def test_a_missing_robot_file_is_one_error(tmp_path):
    with pytest.raises(ConfigError, match=r"nope\.urdf\.xacro: no such file"):
        model_from_file(tmp_path / "nope.urdf.xacro")


def test_a_closed_cell_with_the_robot_is_freed():
    import gc
    import weakref

    from omtp_drake.cell.lifetime import python_systems
    from omtp_drake.script import Cell

    with Cell(robot=ROBOT) as cell:
        cell.wait(0.1)
        refs = {s.get_name(): weakref.ref(s) for s in python_systems(cell.runtime.diagram)}
        refs |= {"plant": weakref.ref(cell.station.plant), "context": weakref.ref(cell.runtime.context)}
    assert "tip_camera.noise" in refs
    del cell
    gc.collect()
    gc.collect()
    assert sorted(name for name, ref in refs.items() if ref() is not None) == []
