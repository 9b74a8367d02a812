"""A model's camera nobody reads costs no renderer and no render; read later, its images are
those of its last sample, as Drake's RgbdSensor renders the scene at that sample's poses
(the URDF tutorial's robot, tests/fixtures/tutorial_ws: a depth camera at 20 Hz on a slider)."""

from pathlib import Path

import numpy as np
import pytest
from pydrake.geometry import ClippingRange, ColorRenderCamera, DepthRange, DepthRenderCamera, RenderCameraCore
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.systems.analysis import Simulator
from pydrake.systems.sensors import RgbdSensor

from omtp_drake.cell.depth_camera import (
    GAZEBO_RENDERER,
    add_gazebo_renderer,
    camera_info,
    depth_range,
)
from omtp_drake.cell.logical_camera import X_CameraOptical
from omtp_drake.cell.station import build_station
from omtp_drake.scenario import Scenario, model_from_file
from omtp_drake.workspace import Workspace

FIXTURE = Path(__file__).parent / "fixtures" / "tutorial_ws" / "src"
ROBOT = FIXTURE / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
#: A sample time of the 20 Hz camera, and a read between it and the next.
SAMPLE, READ = 0.1, 0.13


@pytest.fixture(scope="module")
def run():
    """The station with the slider moving (the camera with it), run to SAMPLE."""
    robot = model_from_file(ROBOT, Workspace.from_dirs([FIXTURE], environ={}))
    station = build_station(Scenario(name="empty_world", models=[robot]))
    context = station.create_context()
    plant = station.plant
    plant.GetJointByName("slider_joint").set_translation_rate(plant.GetMyMutableContextFromRoot(context), 2.0)
    simulator = Simulator(station.diagram, context)
    simulator.AdvanceTo(SAMPLE)  # (the sample at SAMPLE is taken at the next step's start)
    return station, simulator


def _drake_images(station, context):
    """Drake's RgbdSensor on the camera, rendering the scene of ``context`` now."""
    sensor = station.depth_cameras["tip_camera"].config
    parent = station.plant.GetBodyFrameIdIfExists(station.plant.GetBodyByName(sensor.link).index())
    camera = sensor.camera
    core = RenderCameraCore(
        GAZEBO_RENDERER,
        camera_info(sensor, pixel_centres_at_integers=False),
        ClippingRange(camera.near, camera.far),
        RigidTransform(),
    )
    X_PO = RigidTransform(RollPitchYaw(sensor.rpy), sensor.xyz) @ X_CameraOptical()
    rgbd = RgbdSensor(
        parent,
        X_PO,
        ColorRenderCamera(core, False),
        DepthRenderCamera(core, DepthRange(*depth_range(sensor))),
    )
    scene_graph = station.scene_graph
    scene_context = scene_graph.GetMyMutableContextFromRoot(context)
    add_gazebo_renderer(scene_graph, scene_context)
    rgbd_context = rgbd.CreateDefaultContext()
    rgbd.query_object_input_port().FixValue(
        rgbd_context, scene_graph.get_query_output_port().Eval(scene_context)
    )
    return [
        np.array(port.Eval(rgbd_context).data, copy=True)
        for port in (rgbd.color_image_output_port(), rgbd.depth_image_32F_output_port())
    ]


def test_a_camera_nobody_reads_has_no_renderer_and_renders_nothing(run):
    station, simulator = run
    render = station.diagram.GetSubsystemByName("tip_camera.rgbd")
    scene_graph = station.scene_graph
    assert scene_graph.RendererCount() == 0
    assert not scene_graph.HasRenderer(
        scene_graph.GetMyContextFromRoot(simulator.get_context()), GAZEBO_RENDERER
    )
    assert not render.has_renderer()


def test_read_later_the_images_are_those_of_the_last_sample(run):
    station, simulator = run
    context = simulator.get_context()
    # Run after the other test: this one renders.
    render = station.diagram.GetSubsystemByName("tip_camera.rgbd")
    assert not render.has_renderer()
    at_sample = _drake_images(station, context)  # the scene the sample at SAMPLE holds
    simulator.AdvanceTo(READ)
    read = [
        np.array(render.GetOutputPort(port).Eval(render.GetMyContextFromRoot(context)).data, copy=True)
        for port in ("color_image", "depth_image_32f")
    ]
    now = _drake_images(station, context)
    assert render.has_renderer()
    assert not np.array_equal(now[1], at_sample[1])  # the camera moved since the sample
    assert np.array_equal(read[0], at_sample[0]) and np.array_equal(read[1], at_sample[1])
    depth = np.asarray(station.diagram.GetOutputPort("tip_camera.depth_image").Eval(context).data)
    assert np.array_equal(depth, at_sample[1])
    color = np.asarray(station.diagram.GetOutputPort("tip_camera.color_image").Eval(context).data)
    assert (
        color.shape == (480, 640, 4) and 0 < np.abs(color[..., :3].astype(int) - read[0][..., :3]).mean() < 5
    )
