"""What a student adds to a course model of their world is loaded as written: the group's
workspace (tests/fixtures/group_ws) with their conveyor model holding a tray beside the belt
(tests/fixtures/rail_edits, the course's layout: a link in the static ``conveyor_belt_fixed``),
and their camera 1 with a mount plate, a lens hood and a loose cable (tests/fixtures/camera_edits).
The conveyor is still the course's belt (its plugin recognised); the tray is a body where
the world's include and the model's poses put it, and a part dropped on it stays there."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from omtp_drake.cli import main
from omtp_drake.launch import own_cell

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    src = tmp_path_factory.mktemp("rail_ws") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    shutil.copytree(FIXTURES / "rail_edits", src, dirs_exist_ok=True)
    for n in (1, 2):
        camera = src / "omtp_gazebo" / "models" / f"logical_camera{n}" / "model.sdf"
        shutil.copyfile(FIXTURES / "camera_edits" / f"logical_camera{n}.sdf", camera)
    return src


@pytest.fixture(scope="module")
def cell(workspace):
    return own_cell(LAUNCH, workspace=[workspace], environ={})


def _X(x: float, y: float, z: float, yaw: float) -> np.ndarray:
    X = np.eye(4)
    X[:3, :3] = [[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]]
    X[:3, 3] = [x, y, z]
    return X


#: The tray in world, from the files' numbers: the world's <include> pose of the conveyor
#: (1.2 5 0, yaw -1.5708) and the tray link's <pose> in the static nested model (2 0.6 0.9, yaw 0.1).
X_W_TRAY = _X(1.2, 5.0, 0.0, -1.5708) @ _X(2.0, 0.6, 0.9, 0.1)
TRAY_TOP = 0.9 + 0.02


def test_their_tray_is_a_model_of_their_cell_and_the_belt_stays_the_courses(cell):
    models = {m.name: m for m in cell.scenario.models}
    tray = models["conveyor_belt_own"]
    assert tray.static and tray.format == "sdf"
    sdf = ET.fromstring(tray.description)
    assert [link.get("name") for link in sdf.iter("link")] == ["reject_tray"]
    assert sdf.find(".//link/collision/geometry/box/size").text == "1.0 0.5 0.04"
    # The course's pieces of the same world: the belt, the wall, the cameras.
    assert cell.scenario.conveyor is not None and cell.scenario.deletion_wall
    assert not [w for w in cell.warnings if "reject_tray" in w], cell.warnings


@pytest.fixture(scope="module")
def runtime(cell):
    from omtp_drake.sim.runtime import FactoryRuntime

    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    yield runtime
    runtime.close()


def test_their_tray_stands_where_the_world_puts_it_and_holds_a_part(runtime):
    from pydrake.math import RigidTransform

    plant = runtime.station.plant
    context = plant.GetMyContextFromRoot(runtime.context)
    X_WT = plant.GetBodyByName("reject_tray").EvalPoseInWorld(context).GetAsMatrix4()
    np.testing.assert_allclose(X_WT, X_W_TRAY, atol=1e-3)
    part = runtime.pool.spawn(runtime.context, RigidTransform(X_W_TRAY[:3, 3] + [0.0, 0.0, 0.25]))
    runtime.advance(1.5)
    p = plant.GetBodyByName(part).EvalPoseInWorld(context).translation()
    # On the tray (not on the floor 0.9 m below): its top under the part, the part over it.
    assert TRAY_TOP < p[2] < TRAY_TOP + 0.15, p
    p_T = np.linalg.inv(X_W_TRAY) @ [*p, 1.0]
    assert abs(p_T[0]) < 0.5 and abs(p_T[1]) < 0.25, p_T


def test_their_tray_is_welded_to_the_cells_conveyor_and_part_of_its_gazebo_model(cell, runtime):
    from omtp_drake.cell.gazebo_models import gazebo_models

    assert {m.name: m.parent for m in cell.scenario.models}["conveyor_belt_own"] == "conveyor_base"
    plant = runtime.station.plant
    tray = plant.GetBodyByName("reject_tray")
    (joint,) = [plant.get_joint(j) for j in plant.GetJointIndices(tray.model_instance())]
    assert joint.parent_body().name() == "conveyor_base" and joint.num_velocities() == 0
    models = {m.name: m for m in gazebo_models(plant, cell.scenario)}
    assert tray.model_instance() in models["conveyor_belt"].instances and "conveyor_belt_own" not in models


def test_tf_echo_gives_their_tray(workspace, capsys):
    argv = ["tf-echo", "--launch", LAUNCH, "--workspace", str(workspace), "world", "reject_tray", "--json"]
    assert main(argv) == 0, capsys.readouterr().err
    echoed = json.loads(capsys.readouterr().out)["translation"]
    np.testing.assert_allclose(echoed, X_W_TRAY[:3, 3], atol=1e-3)


def test_their_view_of_the_world_shows_the_tray_in_their_conveyor(workspace, capsys):
    world = workspace / "omtp_gazebo" / "worlds" / "lecture6_assignment1.world"
    assert main(["view", str(world), "--workspace", str(workspace), "--json"]) == 0, capsys.readouterr().err
    models = {m["name"]: m for m in json.loads(capsys.readouterr().out)["models"]}
    assert {"link", "reject_tray", "belt"} == set(models["conveyor_belt"]["links"])


def test_what_would_move_on_a_course_model_is_one_warning_each(workspace):
    from omtp_drake.launch.sdf_world import world_model
    from omtp_drake.launch.world_additions import additions
    from omtp_drake.workspace import Workspace

    text = (workspace / "omtp_gazebo" / "models" / "conveyor" / "model.sdf").read_text()
    element = ET.fromstring(text).find("model")
    top = ET.SubElement(element, "link", name="loose_plate")  # a free link of the top model
    ET.SubElement(ET.SubElement(top, "visual", name="v"), "geometry").append(
        ET.fromstring("<box><size>1 1 1</size></box>")
    )
    belt = element.find("model[@name='conveyor_belt_moving']/link[@name='belt']")
    ET.SubElement(belt, "collision", name="cleat").append(
        ET.fromstring("<geometry><sphere><radius>0.1</radius></sphere></geometry>")
    )
    model = world_model("conveyor_belt", (1.2, 5.0, 0.0, 0.0, 0.0, -1.5708), element, "conveyor.sdf")
    from pydrake.math import RigidTransform

    entry, warnings = additions(model, "conveyor", Workspace(), ("conveyor_base", RigidTransform()))
    assert entry is not None and [
        link.get("name") for link in ET.fromstring(entry.description).iter("link")
    ] == ["reject_tray"]
    assert len(warnings) == 2
    plate, cleat = warnings
    assert "link 'loose_plate' of model 'conveyor_belt' moves" in plate and "not loaded" in plate
    assert "cleat of the course's link 'conveyor_belt_moving::belt'" in cleat and "not loaded" in cleat


#: Camera 1 in world (the world's include: 1.2 2.0 1.95, pitched 90 deg: its x looks down).
X_W_CAMERA = np.array([[0.0, 0.0, 1.0, 1.2], [0.0, 1.0, 0.0, 2.0], [-1.0, 0.0, 0.0, 1.95], [0, 0, 0, 1.0]])


def test_what_they_added_to_a_camera_is_loaded_as_written_on_the_cells_camera(cell, runtime):
    """The plate inside the camera's link and the hood held to it: one model entry hung on
    the cell's camera frame, where the file puts them; the loose cable is one warning."""
    from omtp_drake.cell.gazebo_models import gazebo_models

    own = {m.name: m for m in cell.scenario.models}["logical_camera_1_own"]
    assert own.parent == "logical_camera_1_frame"
    sdf = ET.fromstring(own.description)
    assert [link.get("name") for link in sdf.iter("link")] == ["logical_camera_1_link_own", "lens_hood"]
    plate = sdf.find(".//link[@name='logical_camera_1_link_own']")
    assert [c.get("name") for c in plate.iter("collision")] == ["collision", "mount_plate_collision"]
    (cable,) = [w for w in cell.warnings if "loose_cable" in w]
    assert "logical_camera1/model.sdf" in cable and "not loaded" in cable
    plant = runtime.station.plant
    context = plant.GetMyContextFromRoot(runtime.context)
    X_WH = plant.GetBodyByName("lens_hood").EvalPoseInWorld(context).GetAsMatrix4()
    np.testing.assert_allclose(X_WH, X_W_CAMERA @ _X(0.06, 0.0, 0.0, 0.0), atol=1e-3)
    X_WP = plant.GetBodyByName("logical_camera_1_link_own").EvalPoseInWorld(context).GetAsMatrix4()
    np.testing.assert_allclose(X_WP, X_W_CAMERA, atol=1e-3)  # (the plate's pose is its collision's)
    # Part of the camera's Gazebo model; the cell's camera frame is where it was.
    models = {m.name: m for m in gazebo_models(plant, cell.scenario)}
    hood = plant.GetBodyByName("lens_hood").model_instance()
    assert hood in models["logical_camera_1"].instances and "logical_camera_1_own" not in models
    X_WC = plant.GetFrameByName("logical_camera_1_frame").CalcPoseInWorld(context).GetAsMatrix4()
    np.testing.assert_allclose(X_WC, X_W_CAMERA, atol=1e-5)  # (the world writes 1.5708)


def _geometries(runtime, body: str) -> dict[str, list[tuple[str, np.ndarray, np.ndarray]]]:
    """``role -> [(shape, corners low and high in the body's frame)]`` of ``body``'s geometry."""
    plant, inspector = runtime.station.plant, runtime.station.scene_graph.model_inspector()
    b = plant.GetBodyByName(body)
    found: dict[str, list[tuple[str, np.ndarray, np.ndarray]]] = {}
    for role, ids in (
        ("collision", plant.GetCollisionGeometriesForBody(b)),
        ("visual", plant.GetVisualGeometriesForBody(b)),
    ):
        for g in ids:
            shape, X_BG = inspector.GetShape(g), inspector.GetPoseInFrame(g)
            if type(shape).__name__ == "Box":
                corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
                vertices = corners * shape.size() / 2
            else:  # a mesh: its convex hull's vertices (the mesh file's, scaled)
                hull = shape.GetConvexHull()
                vertices = np.array([hull.vertex(i) for i in range(hull.num_vertices())])
            p_BV = (X_BG.GetAsMatrix4() @ np.c_[vertices, np.ones(len(vertices))].T).T[:, :3]
            found.setdefault(role, []).append((type(shape).__name__, p_BV.min(0), p_BV.max(0)))
    return found


def test_the_courses_camera_housing_is_its_mesh_as_the_model_writes_it(runtime):
    """The course's camera.dae (tests/camera_meshes.py: its 79.4 x 57.9 x 128.1 mm, in mm
    units) at ``0 0.02 0``, turned -1.5708 about z in the camera's link, as visual and
    collision on the cell's camera; the cell's stand-in housing is not drawn beside it."""
    own = _geometries(runtime, "logical_camera_1_link_own")
    # The mesh turned a quarter: its y is the link's x, its -x the link's y (plus 0.02).
    low, high = np.array([-0.0381, 0.02 - 0.0397, -0.0678]), np.array([0.0197, 0.02 + 0.0397, 0.0603])
    for role in ("collision", "visual"):
        (mesh,) = [g for g in own[role] if g[0] != "Box"]  # (beside it: their mount plate)
        np.testing.assert_allclose(mesh[1], low, atol=2e-4)
        np.testing.assert_allclose(mesh[2], high, atol=2e-4)
    assert _geometries(runtime, "logical_camera_1_frame") == {}


def test_their_own_camera_housing_is_loaded_as_written_and_the_camera_still_sees(runtime):
    """Camera 2's housing of theirs (a 0.12 x 0.06 x 0.04 box 3 cm forward and 1 cm up,
    no collision): that box, where they put it, and nothing that collides; the camera
    is the plugin's as before (over robot 2's bin, it sees the bin, not itself)."""
    own = _geometries(runtime, "logical_camera_2_link_own")
    assert list(own) == ["visual"]
    ((shape, low, high),) = own["visual"]
    assert shape == "Box"
    np.testing.assert_allclose(low, [0.03 - 0.06, -0.03, 0.01 - 0.02], atol=1e-9)
    np.testing.assert_allclose(high, [0.03 + 0.06, 0.03, 0.01 + 0.02], atol=1e-9)
    assert _geometries(runtime, "logical_camera_2_frame") == {}
    runtime.sample_cameras()
    seen = [m.name for m in runtime.camera_image("logical_camera_2").models]
    assert "bin_1_" in seen and not [s for s in seen if s.startswith("logical_camera")], seen


def _wall(text: str, tmp_path: Path):
    from omtp_drake.launch.sdf_world import world_model
    from omtp_drake.launch.xml_lines import parse_xml

    path = tmp_path / "model.sdf"
    path.write_text(text)
    doc = parse_xml(path)
    return world_model(
        "deletion_wall", (1.2, -5.1, 1.425, 0, 0, 1.5708), doc.root.find("model"), str(path), doc=doc
    )


def test_a_changed_course_element_is_told_at_its_line_with_both_shapes(workspace, tmp_path):
    """Their wall's collision made wider differs from the cell's box, said at the element's
    line (the world then loads their wall as written: tests/test_moved_pieces.py); the
    course's own box, as written, is the cell's."""
    from pydrake.math import RigidTransform

    from omtp_drake.launch.world_additions import additions, wall_changed
    from omtp_drake.workspace import Workspace

    course = (workspace / "omtp_gazebo" / "models" / "deletion_wall" / "model.sdf").read_text()
    body = ("deletion_wall", RigidTransform())
    assert additions(_wall(course, tmp_path), "deletion_wall", Workspace(), body) == (None, [])
    assert not wall_changed(_wall(course, tmp_path))
    wider = course.replace("<size>0.1 1 1</size>", "<size>0.1 2 1</size>", 1)
    assert wall_changed(_wall(wider, tmp_path))
    entry, warnings = additions(_wall(wider, tmp_path), "deletion_wall", Workspace(), body)
    line = 1 + wider[: wider.index('<collision name="collision"')].count("\n")
    assert entry is None and warnings == [
        f"{tmp_path / 'model.sdf'}:{line}: <collision name='collision'> of the course's link 'sensing_link' "
        "in model 'deletion_wall' is box 0.1 2 1 at 0 0 0; the cell's deletion_wall is its own "
        "(0.1 x 1 x 1 at 0 0 0) and keeps it: not loaded (the plugin's behaviour is on the cell's body)"
    ]


def test_a_belt_box_is_the_cells_belt_as_written_another_shape_is_one_line(workspace):
    """The course's belt_collision is 6 mm thick at -3 mm (the fixtures' 1 cm at -5 mm), a
    raised one 2 cm higher: each a box along the belt, which the cell's belt is made as (no
    line; ``tests/test_moved_pieces.py`` rides one); a cylinder is one line (the cell keeps
    its own belt)."""
    from pydrake.math import RigidTransform

    from omtp_drake.launch.sdf_world import world_model
    from omtp_drake.launch.world_additions import belt_box, changed_lines

    text = (workspace / "omtp_gazebo" / "models" / "conveyor" / "model.sdf").read_text()
    model = world_model(
        "conveyor_belt", (1.2, 5.0, 0.0, 0.0, 0.0, -1.5708), ET.fromstring(text).find("model"), "c.sdf"
    )
    belt = model.element.find("model[@name='conveyor_belt_moving']/link[@name='belt']")
    X_MB = RigidTransform([5.0, 0.0, 0.92 - 0.003])
    belt.find("collision/geometry/box/size").text = "10 0.6 0.006"
    assert belt_box(belt, "c.sdf")[0] == (10.0, 0.6, 0.006)
    assert changed_lines(model, "conveyor", "conveyor_belt_moving::belt", belt, X_MB) == []
    raised = RigidTransform([5.0, 0.0, 0.94 - 0.003])
    assert changed_lines(model, "conveyor", "conveyor_belt_moving::belt", belt, raised) == []
    geometry = belt.find("collision/geometry")
    geometry.remove(geometry.find("box"))
    ET.SubElement(geometry, "cylinder")
    assert belt_box(belt, "c.sdf") is None
    (line,) = changed_lines(model, "conveyor", "conveyor_belt_moving::belt", belt, raised)
    assert line.startswith("c.sdf: <collision name='belt_collision'>") and "is no box at 5 0 0.937" in line
