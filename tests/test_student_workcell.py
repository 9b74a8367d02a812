"""A student's edits to the course's own pieces are loaded as written: the group's workspace
(tests/fixtures/group_ws) with their workcell xacro holding a shelf they added
(tests/fixtures/shelf_edits, the course's layout), a part spawned onto it by their launch.
The shelf is a body of the plant where xacro and the joint chain put it, the part rests
on it, tf knows both; the course's pieces in the same files still work."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from bin_meshes import write_bin_meshes
from camera_meshes import without_cameras
from fixture_reports import assert_as_recorded

from omtp_drake.cli import main
from omtp_drake.launch import own_cell

FIXTURES = Path(__file__).resolve().parent / "fixtures"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
#: The shelf's board top (m) and the sorted part's half edge.
SHELF_TOP, PART_HALF = 0.6, 0.05


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    """The group's workspace with the student's edits copied over it (and their bin's meshes)."""
    src = tmp_path_factory.mktemp("shelf_ws") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    shutil.copytree(FIXTURES / "shelf_edits", src, dirs_exist_ok=True)
    write_bin_meshes(src / "omtp_support" / "meshes" / "bin")
    return src


@pytest.fixture(scope="module")
def cell(workspace):
    return own_cell(LAUNCH, workspace=[workspace], environ={})


def _rpy(r: float, p: float, y: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


@pytest.fixture(scope="module")
def independent(workspace, tmp_path_factory) -> dict[str, np.ndarray]:
    """X_WL (4x4) of the workcell's links: xacro's own command line (``$(find)`` through an
    ament prefix written here by hand), then the fixed joints' chain from its root (the
    launch spawns the workcell at the origin)."""
    prefix = tmp_path_factory.mktemp("ament")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / "omtp_support").touch()
    (prefix / "share" / "omtp_support").symlink_to(workspace / "omtp_support")
    xacro = Path(sys.executable).parent / "xacro"
    env = {**os.environ, "AMENT_PREFIX_PATH": str(prefix)}
    file = workspace / "omtp_support" / "urdf" / "workcell" / "workcell.xacro"
    out = subprocess.run([str(xacro), str(file)], env=env, capture_output=True, text=True, check=True)
    urdf = ET.fromstring(out.stdout)
    X = {"world_interface": np.eye(4)}
    joints = urdf.findall("joint")
    while len(X) < len(joints) + 1:
        for joint in joints:
            parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
            if parent in X and child not in X:
                origin = joint.find("origin")
                X_PC = np.eye(4)
                X_PC[:3, :3] = _rpy(*[float(v) for v in origin.get("rpy", "0 0 0").split()])
                X_PC[:3, 3] = [float(v) for v in origin.get("xyz", "0 0 0").split()]
                X[child] = X[parent] @ X_PC
    return X


@pytest.fixture(scope="module")
def runtime(cell):
    from omtp_drake.sim.runtime import FactoryRuntime

    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    yield runtime
    runtime.close()


def _X_WF(runtime, frame: str) -> np.ndarray:
    plant = runtime.station.plant
    context = plant.GetMyContextFromRoot(runtime.context)
    return plant.GetFrameByName(frame).CalcPoseInWorld(context).GetAsMatrix4()


def test_the_shelf_they_added_is_a_model_of_their_cell_and_the_course_pieces_stay(cell):
    models = {m.name: m for m in cell.scenario.models}
    pedestals = ["robot1_pedestal", "robot2_pedestal"]
    housings = ["logical_camera_1_own", "logical_camera_2_own"]  # (their camera.dae, as written)
    theirs = ["bin_1_", "bin_2_", "fit_crate", *housings, *pedestals, "sorted_part", "workcell"]
    assert sorted(models) == theirs
    assert [r.pedestal_model for r in cell.scenario.robots] == pedestals
    shelf = ET.fromstring(models["workcell"].description)
    assert [link.get("name") for link in shelf.findall("link")] == ["world", "parts_shelf"]
    assert models["workcell"].static
    # The course's pieces of the same launch: the arms, bins, beam, belt, wall, cameras.
    scenario = cell.scenario
    assert [r.name for r in scenario.robots] == ["robot1", "robot2"]
    assert sorted(b.name for b in scenario.bins) == ["bin_1", "bin_2"]
    assert scenario.break_beam and scenario.deletion_wall and scenario.conveyor is not None
    assert len(scenario.cameras) == 2
    # A frame-only link of theirs stays a frame (as before), the shelf is a body, not both.
    frames = {f.name for f in scenario.frames}
    assert "parts_shelf_label" in frames and "parts_shelf" not in frames


def test_the_shelf_stands_where_xacro_and_the_joint_chain_put_it(runtime, independent):
    # (not where the course's files put anything: -3.0, 3.5 in the world, turned 90 deg + 0.3)
    np.testing.assert_allclose(independent["parts_shelf"][:3, 3], [-3.0, 3.5, 0.0], atol=1e-9)
    plant = runtime.station.plant
    assert plant.HasBodyNamed("parts_shelf")
    for link in ("parts_shelf", "parts_shelf_label", "workcell"):
        X = _X_WF(runtime, link)
        np.testing.assert_allclose(X[:3, 3], independent[link][:3, 3], atol=1e-3, err_msg=link)
        assert np.abs(X[:3, :3] - independent[link][:3, :3]).max() < 1e-3, link


def test_the_part_they_spawn_onto_the_shelf_rests_on_it(runtime, workspace, capsys):
    np.testing.assert_allclose(_X_WF(runtime, "sorted_part_link")[:3, 3], [-3.0, 3.5, 0.7], atol=1e-6)
    runtime.advance_to(1.5)
    rested = _X_WF(runtime, "sorted_part_link")[:3, 3]
    np.testing.assert_allclose(rested, [-3.0, 3.5, SHELF_TOP + PART_HALF], atol=0.01)
    # tf-echo, as a student asks it, says the same.
    argv = ["tf-echo", "--launch", LAUNCH, "--workspace", str(workspace), "--time", "1.5"]
    assert main([*argv, "world", "sorted_part_link", "--json"]) == 0, capsys.readouterr().err
    echoed = json.loads(capsys.readouterr().out)["translation"]
    np.testing.assert_allclose(echoed, rested, atol=1e-3)


def test_their_wider_bin_is_loaded_as_they_wrote_it(cell, runtime):
    """Their bin of plates (0.6 m outer, 2 cm walls, 5 cm floor, 0.4 m high) is the bin in the
    plant, where their launch puts it; the cell's in-bin test and drop slots use its walls."""
    from pydrake.geometry import Box, Role

    bins = {b.name: b for b in cell.scenario.bins}
    assert bins["bin_2"].model == "bin_2_" and bins["bin_2"].walls == [0.28, 0.28, 0.05, 0.4]
    geometry = bins["bin_2"].geometry
    assert (geometry.inner_half_x, geometry.inner_half_y, geometry.floor_top) == (0.28, 0.28, 0.05)
    plant, inspector = runtime.station.plant, runtime.station.scene_graph.model_inspector()
    body = plant.GetBodyByName("bin_2_base_link")
    assert plant.GetModelInstanceName(body.model_instance()) == "bin_2_"
    ids = inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(body.index()), Role.kProximity)
    sizes = sorted(
        tuple(round(float(v), 6) for v in (shape.width(), shape.depth(), shape.height()))
        for shape in (inspector.GetShape(i) for i in ids)
        if isinstance(shape, Box)
    )
    assert sizes == sorted(
        [(0.6, 0.6, 0.05), (0.02, 0.6, 0.4), (0.02, 0.6, 0.4), (0.56, 0.02, 0.4), (0.56, 0.02, 0.4)]
    )
    np.testing.assert_allclose(_X_WF(runtime, "bin_2_drop_point")[:3, 3], [-0.1, 2.5, 1.0], atol=1e-9)


def test_a_crate_by_the_wall_of_their_bin_lands_on_its_floor(cell, runtime):
    """Dropped 0.22 m off the bin's axis (beyond the catalogue bin's 0.19 m walls), it lands
    on their bin's floor, and the cell counts it in the bin."""
    runtime.advance_to(max(runtime.time, 1.5))
    p = _X_WF(runtime, "fit_crate_link")[:3, 3]
    np.testing.assert_allclose(p, [0.12, 2.5, 0.05 + PART_HALF], atol=0.01)
    assert cell.scenario.bin("bin_2").contains(p)


def test_their_view_of_the_workcell_lists_the_shelf(workspace, capsys):
    argv = ["view", "--launch", LAUNCH, "--workspace", str(workspace), "--param", "/workcell_description"]
    assert main([*argv, "--json"]) == 0, capsys.readouterr().err
    info = json.loads(capsys.readouterr().out)
    assert {"workcell", "parts_shelf", "parts_shelf_label"} <= set(info["links"])


def test_their_belt_script_still_puts_parts_in_their_bin(workspace, tmp_path):
    """The course's pieces in their edited files still work: robot 1's belt script (the
    group's, unchanged) picks a part off the belt into their wider bin. (One part: the
    spawner's period is 10 s; two parts, one of each kind, go into the bin of the unedited
    workspace in test_group_workspace.py's test_their_belt_script_puts_parts_in_their_bin_next_to_robot_1.)"""
    script = workspace / "omtp_lecture6" / "scripts" / "belt_to_bin_robot1.py"
    out = tmp_path / "report.json"
    argv = ["ros-run", str(script), "1", "--launch", LAUNCH, "--workspace", str(workspace)]
    assert main([*argv, "--timeout", "60", "--json", str(out), "-q"]) == 0
    report = json.loads(out.read_text())
    assert report["exception"] is None, report["traceback"]
    assert report["ledger"]["in_bin"]["bin_2"] >= 1, report["ledger"]
    assert_as_recorded("workcell edits belt_to_bin_robot1.py 1", report)


ARM_WITH_MOUNT = """<robot name="robot1">
  <link name="world"/>
  <link name="robot1_base_link"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="robot1_shoulder_link"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="camera_mount"><visual><geometry><box size="0.05 0.05 0.02"/></geometry></visual></link>
  <link name="tool_rack"><collision><geometry><box size="0.5 0.2 0.02"/></geometry></collision></link>
  <link name="rack_frame"/>
  <joint name="base" type="fixed"><parent link="world"/><child link="robot1_base_link"/></joint>
  <joint name="pan" type="revolute"><parent link="robot1_base_link"/><child link="robot1_shoulder_link"/>
    <axis xyz="0 0 1"/></joint>
  <joint name="mount" type="fixed"><parent link="robot1_shoulder_link"/><child link="camera_mount"/></joint>
  <joint name="rack" type="fixed"><parent link="world"/><child link="tool_rack"/>
    <origin xyz="1 2 0.5" rpy="0 0 0.5"/></joint>
  <joint name="rack_frame" type="fixed"><parent link="tool_rack"/><child link="rack_frame"/></joint>
</robot>"""


def test_a_link_on_a_pieces_moving_joint_hangs_on_it_a_still_one_is_loaded():
    from pydrake.math import RigidTransform, RollPitchYaw

    from omtp_drake.launch.own_links import mounts, own_links, own_links_urdf
    from omtp_drake.launch.urdf_model import UrdfModel

    model = UrdfModel.from_text(ARM_WITH_MOUNT, "arm.urdf")
    links, warnings = own_links(model, ["robot1_"], "arm.urdf")
    assert links == ["tool_rack"] and warnings == []  # (rack_frame: no geometry, a frame as before)
    (mount,) = mounts(model, ["robot1_"])  # (tests/test_arm_links.py: the cell welds it to the arm)
    assert (mount.root, mount.parent, mount.links) == (
        "camera_mount",
        "robot1_shoulder_link",
        ("camera_mount",),
    )
    X_WM = RigidTransform(RollPitchYaw(0, 0, 0.1), [0.5, 0, 0])
    text = ET.fromstring(own_links_urdf(model, links, X_WM, {}, "robot1_extras"))
    (joint,) = text.findall("joint")
    X_WL = X_WM @ RigidTransform(RollPitchYaw(0, 0, 0.5), [1, 2, 0.5])
    np.testing.assert_allclose(
        [float(v) for v in joint.find("origin").get("xyz").split()], X_WL.translation()
    )
    assert text.find("link[@name='tool_rack']/collision/geometry/box").get("size") == "0.5 0.2 0.02"


def test_a_bin_of_boxes_gives_its_walls_a_mesh_bin_none():
    from omtp_drake.launch.own_links import bin_walls
    from omtp_drake.launch.urdf_model import UrdfModel

    def bin_of(collisions: str) -> UrdfModel:
        return UrdfModel.from_text(
            f'<robot name="b"><link name="b_base_link">{collisions}</link></robot>', "b"
        )

    def box(x: float, y: float, z: float, size: str) -> str:
        return f'<collision><origin xyz="{x} {y} {z}"/><geometry><box size="{size}"/></geometry></collision>'

    walls = (
        box(0, 0, 0.05, "0.5 0.4 0.1")
        + box(0.24, 0, 0.2, "0.02 0.4 0.4")
        + box(0, -0.19, 0.2, "0.5 0.02 0.4")
    )
    assert bin_walls(bin_of(walls), "b_base_link") == [0.23, 0.18, 0.1, 0.4]  # (its rectangle)
    mesh = (
        '<collision><geometry><mesh filename="package://omtp_support/meshes/bin.dae"/></geometry></collision>'
    )
    assert bin_walls(bin_of(walls + mesh), "b_base_link") is None
    assert bin_walls(bin_of(box(0, 0, 0.05, "0.5 0.4 0.1")), "b_base_link") is None  # a floor, no walls


def test_their_pedestals_are_the_arms_pedestals_as_their_files_write_them(runtime):
    """Robot 2's pedestal is 0.695 m high in their launch (its arm stands at 0.7 m, as their
    robot_system puts it): the pedestal in the plant is theirs, 5 mm under the arm, as Gazebo
    shows it; the arm's own links still do not collide with it (one robot)."""
    from pydrake.geometry import Box, Role

    plant, inspector = runtime.station.plant, runtime.station.scene_graph.model_inspector()
    body = plant.GetBodyByName("robot2_pedestal_link")
    assert plant.GetModelInstanceName(body.model_instance()) == "robot2_pedestal"
    (geometry,) = inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(body.index()), Role.kProximity)
    shape = inspector.GetShape(geometry)
    assert isinstance(shape, Box) and shape.height() == pytest.approx(0.695)
    np.testing.assert_allclose(_X_WF(runtime, "robot2_pedestal_link")[:3, 3], [-7.8, -1.5, 0.0], atol=1e-9)
    assert runtime.station.arm("robot2").pedestal == body.model_instance()


def test_their_mesh_bin_is_their_geometry_kept_open(cell, runtime):
    """Bin 1 is the course's bin of meshes (a floor and sides, .dae, scaled 0.6) made
    rectangular and turned a quarter by their launch: it is their model, its inside measured
    on its meshes, its collision convex pieces (one hull per mesh would close it)."""
    from pydrake.geometry import Box, Convex, Role

    bin_1 = cell.scenario.bin("bin_1")
    assert bin_1.model == "bin_1_" and bin_1.yaw == pytest.approx(1.5708)
    np.testing.assert_allclose(bin_1.walls, [0.28, 0.22, 0.05, 0.4], atol=1e-6)
    assert {m.name: m for m in cell.scenario.models}["bin_1_"].open_links == ["bin_1_base_link"]
    station = runtime.station
    plant, inspector = station.plant, station.scene_graph.model_inspector()
    body = plant.GetBodyByName("bin_1_base_link")
    assert plant.GetModelInstanceName(body.model_instance()) == "bin_1_"
    frame = plant.GetBodyFrameIdOrThrow(body.index())
    ids = inspector.GetGeometries(frame, Role.kProximity)
    # Convex pieces; those along its axes are boxes (the floor plate, the walls' slabs).
    shapes = [inspector.GetShape(i) for i in ids]
    assert len(shapes) > 2 and all(isinstance(shape, (Box, Convex)) for shape in shapes)
    boxes = [
        tuple(round(v, 6) for v in (s.width(), s.depth(), s.height())) for s in shapes if isinstance(s, Box)
    ]
    assert (0.6, 0.48, 0.05) in boxes  # (bin_bottom.dae, a closed box: one piece)
    assert len(inspector.GetGeometries(frame, Role.kIllustration)) == 1  # (its visual mesh)
    # Open: the middle of the bin and a point by its wall are outside every piece; inside
    # its floor and its wall are not.
    query = station.scene_graph.get_query_output_port().Eval(
        station.scene_graph.GetMyContextFromRoot(runtime.context)
    )

    def nearest(p_B) -> float:
        p_W = bin_1.X_WB() @ np.asarray(p_B, float)
        found = query.ComputeSignedDistanceToPoint(p_W, 1.0)
        return min(d.distance for d in found if inspector.GetFrameId(d.id_G) == frame)

    assert nearest([0, 0, 0.2]) == pytest.approx(0.15, abs=1e-3)  # 0.15 over the floor
    assert nearest([0.27, 0, 0.3]) == pytest.approx(0.01, abs=1e-3)  # 1 cm from its end wall
    assert nearest([0, 0, 0.03]) < 0 and nearest([0, 0.23, 0.2]) < 0


@pytest.fixture(scope="module")
def loose_parts(cell):
    """The cell of their launch with 0.1 m parts placed by hand (no spawner)."""

    from omtp_drake.sim.runtime import FactoryRuntime

    scenario = without_cameras(cell.scenario, spawner=None, part_pool=4, pool_part_size=0.1)
    scenario.task = None
    runtime = FactoryRuntime(scenario, auto_spawn=False)
    yield runtime
    runtime.close()


def test_a_part_dropped_in_their_mesh_bin_stays_in_it_one_beside_it_does_not(loose_parts):
    """Dropped 0.225 m from the axis along the bin's length (world +y: the bin is turned),
    beyond its narrower half width and the catalogue bin's walls: it lands on the bin's
    floor and the ledger counts it there. One dropped beside its long side is not in it."""
    rt = loose_parts
    inside = rt.spawn_part(xyz=[-8.0, -2.2 + 0.225, 0.6])
    beside = rt.spawn_part(xyz=[-8.0 + 0.32, -2.2, 0.3])
    rt.advance(1.5)
    p = rt.part_pose(inside).translation()
    np.testing.assert_allclose(p, [-8.0, -2.2 + 0.225, 0.05 + 0.05], atol=0.01)
    ledger = rt.ledger()
    assert ledger.parts[inside] == "in_bin:bin_1" and ledger.in_bin["bin_1"] == 1
    assert ledger.parts[beside] != "in_bin:bin_1"
    assert rt.part_pose(beside).translation()[2] < 0.06  # on the floor beside the bin


def test_their_rectangular_bins_drop_spots_reach_its_corners(cell, loose_parts):
    """The script's bin (``cell.bin``) of their mesh bin: its inner size is its rectangle; a
    second part goes to a corner 0.22 m along its length (the narrower half width gave
    0.16), and both are counted in it."""
    from omtp_drake.script.bins import Bin

    rt, config = loose_parts, cell.scenario.bin("bin_1")
    bin_1 = Bin(rt, config)
    np.testing.assert_allclose(bin_1.inner_size, [0.56, 0.44, 0.35], atol=1e-6)
    centre = rt.spawn_part(xyz=bin_1.drop_point())
    rt.advance(1.0)
    spot_B = config.X_WB().inverse() @ bin_1.drop_point()
    np.testing.assert_allclose(spot_B, [-0.22, -0.16, 0.4 + 0.05 + 0.05], atol=1e-6)
    corner = rt.spawn_part(xyz=config.X_WB() @ spot_B)
    rt.advance(1.0)
    assert rt.ledger().parts[centre] == rt.ledger().parts[corner] == "in_bin:bin_1"


def test_a_rectangular_bin_counts_by_its_rectangle_turned_by_its_yaw():
    """Inner 0.56 x 0.44 m, turned a quarter: near the end of its length is in (beyond the
    narrower half width), just past its long wall is out."""
    import math

    from omtp_drake.scenario import BinConfig

    bin_ = BinConfig(name="b", xyz=[1.0, 2.0, 0.0], yaw=math.pi / 2, walls=[0.28, 0.22, 0.05, 0.4])
    assert bin_.contains([1.0, 2.0 + 0.27, 0.2])  # the bin's x is the world's y
    assert not bin_.contains([1.0 + 0.23, 2.0, 0.2])  # across its width: out
    assert bin_.contains([1.0 + 0.21, 2.0, 0.2])
    assert not bin_.contains([1.0, 2.0 + 0.29, 0.2])
    assert not bin_.contains([1.0, 2.0, 0.04])  # under its floor's top


def test_a_mesh_bin_nobody_has_the_meshes_of_is_the_catalogues_with_one_warning():
    from pydrake.math import RigidTransform

    from omtp_drake.launch.pieces import Pieces, add_urdf_model
    from omtp_drake.launch.urdf_model import UrdfModel

    text = """<robot name="bin_3_"><link name="bin_3_base_link"><collision><geometry>
      <mesh filename="package://omtp_support/meshes/bin/collision/bin_sides.dae"/></geometry></collision></link>
      <link name="bin_3_drop_point"/><joint name="j" type="fixed"><parent link="bin_3_base_link"/>
      <child link="bin_3_drop_point"/><origin xyz="0 0 1"/></joint></robot>"""
    pieces = Pieces()
    assert add_urdf_model(
        pieces, UrdfModel.from_text(text, "bin.urdf"), RigidTransform([1, 2, 0]), "bin.urdf", {}
    )
    (bin_3,) = pieces.bins
    assert "model" not in bin_3 and not pieces.own
    assert pieces.warnings == [
        "bin.urdf: bin 'bin_3': its collision meshes cannot be read or hold no floor and walls "
        "around its axis; the catalogue's bin stands in"
    ]


def test_a_bin_of_other_shapes_is_the_catalogues_one_with_no_collision_as_written():
    """Not silently: a bin whose collisions are no box floor and walls (a cylinder) gets one
    line naming where it was spawned and the catalogue's bin; one with no collision at all
    is loaded as written (Gazebo's parts fall through it: ``tests/test_bin_collisions.py``),
    its visual's box measuring nothing, with one line saying so."""
    from pydrake.math import RigidTransform

    from omtp_drake.launch.pieces import Pieces, add_urdf_model
    from omtp_drake.launch.urdf_model import UrdfModel

    where = "spawn.launch:12 (-param /bin_3_description)"
    results = []
    cylinder = '<collision><geometry><cylinder radius="0.3" length="0.05"/></geometry></collision>'
    for collision in (cylinder, ""):
        text = f"""<robot name="bin_3_"><link name="bin_3_base_link"><visual><geometry>
          <box size="0.6 0.6 0.4"/></geometry></visual>{collision}</link>
          <link name="bin_3_drop_point"/><joint name="j" type="fixed"><parent link="bin_3_base_link"/>
          <child link="bin_3_drop_point"/><origin xyz="0 0 1"/></joint></robot>"""
        pieces = Pieces()
        model = UrdfModel.from_text(text, "bin.urdf")
        assert add_urdf_model(pieces, model, RigidTransform([1, 2, 0]), where, {}, "bin_3_")
        results.append(pieces)
    cylinder, bare = results
    (bin_3,) = cylinder.bins
    assert "model" not in bin_3 and not cylinder.own
    assert cylinder.warnings == [
        f"{where}: bin 'bin_3': link 'bin_3_base_link''s collisions (cylinder) are no box floor and "
        "walls; the catalogue's bin stands in"
    ]
    (bin_3,) = bare.bins
    assert bin_3["model"] == "bin_3_" and bin_3["walls"] == [] and [o.name for o in bare.own] == ["bin_3_"]
    assert bare.warnings == [
        f"{where}: bin 'bin_3': link 'bin_3_base_link' has no <collision>; loaded as written, as Gazebo "
        "does: a part dropped in falls through it"
    ]


def test_a_table_they_wrote_inside_the_halls_link_holds_a_part(tmp_path):
    """Their work table written *inside* the workcell's ``workcell`` link (beside the
    course's hall mesh, which the cell's floor, belt and wall stand in for) is loaded as
    written on that link, part of the hall's Gazebo model: a part dropped on it rests on
    its top (without it the part falls to the floor)."""

    from omtp_drake.cell.gazebo_models import gazebo_models
    from omtp_drake.sim.runtime import FactoryRuntime

    src = tmp_path / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    hall = src / "omtp_support" / "urdf" / "workcell" / "workcell.urdf.xacro"
    text = hall.read_text()
    mesh = '<geometry><mesh filename="package://omtp_support/meshes/workcell/visual/workcell.dae"/></geometry>\n'
    mesh += "      </visual>\n"
    table = """      <collision>
        <origin xyz="6 4 0.25" rpy="0 0 0"/>
        <geometry><box size="1 1 0.5"/></geometry>
      </collision>
"""
    assert mesh in text
    hall.write_text(text.replace(mesh, mesh + table))
    cell = own_cell(LAUNCH, workspace=[src], environ={})
    own = {m.name: m for m in cell.scenario.models}["workcell_own"]
    assert own.parent == "workcell"
    scenario = without_cameras(cell.scenario, spawner=None, part_pool=1, pool_part_size=0.1)
    scenario.task = None
    runtime = FactoryRuntime(scenario, auto_spawn=False)
    try:
        models = {m.name: m for m in gazebo_models(runtime.station.plant, scenario)}
        assert "workcell_own" not in models and len(models["workcell_"].instances) == 2
        # The hall's frame is the world turned a quarter: (6, 4) in it is (-4, 6) in the world.
        part = runtime.spawn_part(xyz=[-4.0, 6.0, 1.0])
        runtime.advance(1.0)
        np.testing.assert_allclose(runtime.part_pose(part).translation(), [-4.0, 6.0, 0.55], atol=0.01)
    finally:
        runtime.close()
