"""The RGB-D view of a logical camera: VTK's colour, depth and label images at the
camera's pose and frustum; the renderer only when a camera asks; ``camera --image``;
and the occlusion test's fractions against what VTK's label image shows."""

from dataclasses import replace

import numpy as np
import pytest
import yaml
from matplotlib.image import imread

from omtp_drake.cell.logical_camera import X_CameraOptical
from omtp_drake.cell.rgbd import body_label, camera_info, rgba_array
from omtp_drake.cell.station import build_station
from omtp_drake.cli import main
from omtp_drake.scenario import PartConfig, load_scenario
from omtp_drake.sim.runtime import FactoryRuntime

CAMERA = "logical_camera_1"


def _with_camera(scenario, name, **changes):
    return replace(
        scenario, cameras=[replace(c, **changes) if c.name == name else c for c in scenario.cameras]
    )


@pytest.fixture(scope="module")
def view() -> FactoryRuntime:
    """lecture6_assignment1 with camera 1's RGB-D view (320 x 213), at 0.5 s."""
    runtime = FactoryRuntime(_with_camera(load_scenario("lecture6_assignment1"), CAMERA, rgbd=True))
    runtime.advance_to(0.5)
    runtime.simulator.AdvancePendingEvents()
    return runtime


def _images(runtime: FactoryRuntime, camera: str = CAMERA):
    diagram = runtime.station.diagram
    context = diagram.GetMyContextFromRoot(runtime.context)
    return [
        diagram.GetOutputPort(f"{camera}.{kind}_image").Eval(context) for kind in ("color", "depth", "label")
    ]


def _pixels(runtime: FactoryRuntime, p_W: np.ndarray, camera: str = CAMERA) -> np.ndarray:
    """(u, v, Z): where world points (n, 3) project in the camera's images, and their depth."""
    config = runtime.station.cameras[camera].config
    info = camera_info(config)
    X_WO = runtime.camera_image(camera).X_WC @ X_CameraOptical()
    p_O = (X_WO.inverse().GetAsMatrix34() @ np.c_[p_W, np.ones(len(p_W))].T).T
    return np.c_[
        info.center_x() + info.focal_x() * p_O[:, 0] / p_O[:, 2],
        info.center_y() + info.focal_y() * p_O[:, 1] / p_O[:, 2],
        p_O[:, 2],
    ]


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2D points, counter-clockwise (monotone chain)."""
    points = sorted(map(tuple, points))

    def turn(o, a, b) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    def half(seq):
        chain: list = []
        for p in seq:
            while len(chain) >= 2 and turn(chain[-2], chain[-1], p) <= 0:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    return np.array(half(points) + half(reversed(points)))


def _signed_distance(hull: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Per pixel centre (v, u): distance inside the convex polygon (> 0 inside), in pixels."""
    v, u = np.mgrid[0 : shape[0], 0 : shape[1]]
    q = np.stack([u, v], axis=-1).astype(float)
    distance = np.full(shape, np.inf)
    for a, b in zip(hull, np.roll(hull, -1, axis=0)):
        edge = b - a
        normal = np.array([-edge[1], edge[0]]) / np.linalg.norm(edge)  # inward for CCW in (u, v)
        distance = np.minimum(distance, (q - a) @ normal)
    return distance


def test_renderer_only_when_a_camera_asks(view):
    plain = build_station(load_scenario("lecture6_assignment1"))
    assert plain.scene_graph.RendererCount() == 0
    assert not plain.diagram.HasOutputPort(f"{CAMERA}.color_image")
    assert view.station.scene_graph.RendererCount() == 1
    for kind in ("color", "depth", "label"):
        assert view.station.diagram.HasOutputPort(f"{CAMERA}.{kind}_image")
    assert not view.station.diagram.HasOutputPort("logical_camera_2.color_image")


def test_defaults_leave_the_logical_camera_as_it_was(view):
    """lecture6_assignment1 as shipped: no renderer, the README's image, every fraction
    1.0 and not printed; the RGB-D view changes nothing in the list."""
    plain = FactoryRuntime("lecture6_assignment1")
    plain.advance_to(0.5)
    plain.simulator.AdvancePendingEvents()
    assert plain.station.scene_graph.RendererCount() == 0
    image = plain.camera_image(CAMERA)
    assert not image.occlusion and [(m.name, m.visible_fraction) for m in image.models] == [("object_1", 1.0)]
    text = str(image)
    assert "visible_fraction" not in text and "    x: 0.9790782" in text  # as in README.md
    assert text == str(view.camera_image(CAMERA))


def test_colour_and_label_show_the_part_where_its_box_projects(view):
    color, _, label = _images(view)
    rgba = rgba_array(color)
    assert rgba.shape == (213, 320, 4)  # rgbd_width 320, aspect ratio 1.5
    X_WP = view.part_pose("object_1")
    corners = np.array([[x, y, z] for x in (-0.1, 0.1) for y in (-0.1, 0.1) for z in (-0.1, 0.1)])
    uvz = _pixels(view, (X_WP.rotation().matrix() @ corners.T).T + X_WP.translation())
    inside = _signed_distance(_hull(uvz[:, :2]), rgba.shape[:2])
    r, g, b = (rgba[:, :, k].astype(int) for k in range(3))
    green = (g > r + 30) & (g > b + 30)  # the part's material (0.2, 0.7, 0.25), lit
    assert green[inside > 1.5].all() and not green[inside < -1.5].any()
    assert (inside > 1.5).sum() > 2000  # about 60 x 60 pixels
    labels = np.asarray(label.data)[:, :, 0]
    part = body_label(view.station.plant.GetBodyByName("object_1"))
    assert (labels[inside > 1.5] == part).all()
    assert not (labels[inside < -1.5] == part).any()
    belt = body_label(view.station.plant.GetBodyByName("conveyor_base"))
    assert (labels == belt).sum() > 0.3 * labels.size  # seen beyond far = 1.0, as by a camera


def test_depth_at_the_part_centre_is_the_distance_to_its_top_face(view):
    _, depth, _ = _images(view)
    X_WP = view.part_pose("object_1")
    top = X_WP @ np.array([0.0, 0.0, 0.1])
    ((u, v, z),) = _pixels(view, top[None, :])
    image = np.asarray(depth.data)[:, :, 0]
    assert image[round(v), round(u)] == pytest.approx(z, abs=0.005)
    # Straight down from 2.0 m to the top face at 0.92 + 0.001 + 0.2.
    assert z == pytest.approx(2.0 - 1.121, abs=0.003)
    assert np.isinf(image[0, 0])  # beyond far: the belt at 1.08 m


def test_cli_saves_the_colour_image(tmp_path, capsys):
    scenario = tmp_path / "with_view.yaml"
    scenario.write_text(
        yaml.safe_dump(
            {"base": "lecture6_assignment1", "cameras": [{"name": CAMERA, "rgbd": True, "rgbd_width": 96}]}
        )
    )
    png = tmp_path / "camera1.png"
    assert main(["camera", str(scenario), "--camera", CAMERA, "--image", str(png)]) == 0
    out = capsys.readouterr().out
    assert 'name: "object_1"' in out and f"colour image: {png}" in out
    pixels = imread(png)
    assert pixels.shape == (64, 96, 4)
    assert pixels[32, 48, 1] > pixels[32, 48, 0] + 0.1  # the part (green) in the middle


def test_cli_image_without_a_view_is_one_line(tmp_path, capsys):
    assert (
        main(["camera", "lecture6_assignment1", "--camera", CAMERA, "--image", str(tmp_path / "x.png")]) == 2
    )
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "rgbd: true" in err and "logical_camera_1" in err
    assert not (tmp_path / "x.png").exists()


def test_occlusion_agrees_with_the_rendered_labels():
    """Robot 2 at PreGrasp holds its gripper over a part under camera 2: the part's
    visible fraction is close to (its label pixels) / (its label pixels with the arm
    at Home, out of the view), both rendered by VTK."""
    scenario = load_scenario("omtp_factory")
    scenario.robots = [replace(r, initial_pose="PreGrasp") for r in scenario.robots]
    scenario.parts = [PartConfig(name="object_1", xyz=[-8.25, -1.25, 0.101])]
    scenario = _with_camera(scenario, "logical_camera_2", rgbd=True, rgbd_width=320, occlusion=True)
    runtime = FactoryRuntime(scenario)
    runtime.advance_to(0.2)
    runtime.simulator.AdvancePendingEvents()
    (model,) = [m for m in runtime.camera_image("logical_camera_2").models if m.name == "object_1"]
    part = body_label(runtime.station.plant.GetBodyByName("object_1"))

    def part_pixels() -> int:
        return int((np.asarray(_images(runtime, "logical_camera_2")[2].data) == part).sum())

    hidden = part_pixels()
    runtime.station.set_arm_positions(
        runtime.context, "robot2", [1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0.0]
    )  # R2Home
    shown = part_pixels()
    print(f"visible fraction {model.visible_fraction:.3f}, VTK label pixels {hidden} / {shown}")
    assert 0.2 < hidden / shown < 0.95  # the arm hides some of it
    assert model.visible_fraction == pytest.approx(hidden / shown, abs=0.1)
