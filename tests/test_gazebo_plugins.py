"""The Gazebo plugin layer's rules, as gazebo_ros_pkgs' plugins apply them (no transport):
the camera's info, depths and cloud; the schedulers; what a trajectory request gets
and how its points play on the tutorial robot (tests/fixtures/tutorial_ws)."""

from __future__ import annotations

import dataclasses
import logging
from pathlib import Path

import numpy as np
import pytest
from pydrake.systems.sensors import CameraInfo as DrakeCameraInfo

from omtp_drake.gazebo import messages
from omtp_drake.gazebo.camera import camera_info, gazebo_depths, point_cloud
from omtp_drake.gazebo.joint_pose_trajectory import trajectory_plugins
from omtp_drake.gazebo.schedule import Periodic, Sampled
from omtp_drake.sim.trajectory_request import RequestPoint, TrajectoryRequest

ROBOT = Path(__file__).parent / "fixtures/tutorial_ws/src/slider_arm_description/urdf/slider_arm.urdf.xacro"


def test_camera_info_has_the_plugins_principal_point():
    info = camera_info(1.5, "cam_optical", DrakeCameraInfo(width=4, height=2, fov_y=1.0))
    assert (info.k[2], info.k[5]) == (2.5, 1.5)  # ((w + 1) / 2, (h + 1) / 2)
    assert info.k[0] == info.p[0] and info.p[3] == 0.0 and info.frame_id == "cam_optical"


def test_depths_and_points_out_of_range_are_signed_infinities():
    drake = np.array([[0.0, 1.0, np.inf], [2.0, 2.0, 2.0]], dtype=np.float32)
    depth = gazebo_depths(drake)
    assert depth[0, 0] == -np.inf and depth[0, 2] == np.inf and depth[1, 0] == 2.0
    info = DrakeCameraInfo(width=3, height=2, focal_x=2.0, focal_y=2.0, center_x=1.0, center_y=0.5)
    rgb = np.zeros((2, 3, 3), dtype=np.uint8)
    rgb[1, 2] = (1, 2, 3)
    cloud = point_cloud(0.0, "o", depth, rgb, info)
    assert (cloud.point_step, cloud.row_step, cloud.is_dense) == (32, 96, False)
    raw = np.frombuffer(cloud.data, dtype=np.float32).reshape(2, 3, 8)
    assert np.all(raw[0, 0, :3] == -np.inf) and np.all(raw[0, 2, :3] == np.inf)
    # A pixel's ray through the image centre, scaled to its depth (optical frame: +x right, +y down).
    assert raw[1, 2, :3] == pytest.approx([(2 - 1.0) * 2.0 / 2.0, (1 - 0.5) * 2.0 / 2.0, 2.0])
    assert raw[1, 2, 4:5].view(np.uint32)[0] == 0x010203  # PCL's 0x00RRGGBB
    assert messages.message_fields(cloud)["fields"] == [("x", 0), ("y", 4), ("z", 8), ("rgb", 16)]


def test_periodic_keeps_its_grid_and_sampled_stamps_the_sample():
    periodic = Periodic(0.05, lambda t: t)
    got = [m for t in np.arange(0.0, 0.2, 0.01) for m in periodic(round(t, 2))]
    assert got == [0.0, 0.05, 0.1, 0.15]
    sampled = Sampled(20.0, lambda stamp: stamp)
    assert sampled(0.0) == [0.0] and sampled(0.03) == [] and sampled(0.07) == [0.05] and sampled(0.08) == []


class _RuntimeCell:
    """What the plugin reads of a ``Cell``, on a bare runtime."""

    def __init__(self, runtime):
        self.runtime, self.station = runtime, runtime.station

    @property
    def time(self) -> float:
        return self.runtime.time


@pytest.fixture(scope="module")
def tutorial():
    """The tutorial robot without its camera (the trajectory plugin is all this needs)."""
    from omtp_drake.scenario import with_robot
    from omtp_drake.sim.runtime import FactoryRuntime

    scenario = with_robot(None, ROBOT)
    (model,) = scenario.models
    model = dataclasses.replace(model, gazebo=dataclasses.replace(model.gazebo, sensors=[]))
    runtime = FactoryRuntime(dataclasses.replace(scenario, models=[model]))
    yield runtime, trajectory_plugins(_RuntimeCell(runtime))
    runtime.close()


def _request(frame, names, points, stamp=0.0):
    return TrajectoryRequest(
        tuple(names), tuple(RequestPoint(dt, tuple(q)) for q, dt in points), stamp, frame
    )


def test_a_bad_frame_or_joint_leaves_the_trajectory_unset(tutorial, caplog):
    runtime, (plugin,) = tutorial
    with caplog.at_level(logging.ERROR, logger="gazebo"):
        assert not plugin.receive(_request("", ["slider_joint"], [([0.5], 0.0)]))
        assert not plugin.receive(_request("arm_link", ["slider_joint"], [([0.5], 0.0)]))
        assert not plugin.receive(_request("world", ["elbow"], [([0.5], 0.0)]))
    assert "needs a reference link [] as frame_id" in caplog.text
    assert "Joint [elbow] not found; valid: slider_joint, arm_joint" in caplog.text
    assert caplog.text.count("Trajectory not set.") == 3 and not plugin.edit.playing


def test_points_play_at_the_stamp_and_a_bad_point_is_skipped(tutorial, caplog):
    runtime, (plugin,) = tutorial
    plant = runtime.station.plant
    start = runtime.time + 1.0
    request = _request(
        "map", ["slider_joint", "arm_joint"], [([0.7, 0.5], 1.0), ([0.1], 0.5), ([0.3, 0.2], 0.0)]
    )
    assert plugin.receive(dataclasses.replace(request, stamp=start))

    def q_at(t):
        runtime.advance_to(t)
        context = plant.GetMyContextFromRoot(runtime.context)
        return [plant.GetJointByName(j).GetOnePosition(context) for j in ("slider_joint", "arm_joint")]

    assert q_at(start - 0.1)[0] < 0.05  # not yet
    assert q_at(start) == pytest.approx([0.7, 0.5], abs=1e-9)  # the update at the stamp
    with caplog.at_level(logging.ERROR, logger="gazebo"):
        assert q_at(start + 1.0)[0] == pytest.approx(0.7, abs=0.02)  # point 2 skipped
    assert "point[2] has different number of joint names[2] and positions[1]" in caplog.text
    assert q_at(start + 1.5) == pytest.approx([0.3, 0.2], abs=1e-9)
    assert not plugin.edit.playing
