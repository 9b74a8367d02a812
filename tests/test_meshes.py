"""Every mesh a description names becomes what Drake 1.51 reads (``assets.drake_mesh``,
``assets.drake_ready_meshes``): converted once by content, URIs of every kind resolved,
a mesh nobody has left out with one warning, as Gazebo does."""

import logging
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import trimesh
from pydrake.geometry import Mesh, SceneGraph
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from omtp_drake.assets import drake_mesh, drake_ready_meshes, obj_bounds
from omtp_drake.errors import ConfigError, UnknownNameError

MESHES = Path(__file__).parent / "fixtures" / "franka_ws" / "src" / "fr7_description" / "meshes"
DRAKE = "{http://drake.mit.edu}"


@pytest.fixture(autouse=True)
def _cache(tmp_path, monkeypatch):
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))


def _hull_bounds(path: Path) -> np.ndarray:
    hull = Mesh(str(path)).GetConvexHull()
    vertices = np.array([hull.vertex(i) for i in range(hull.num_vertices())])
    return np.array([vertices.min(axis=0), vertices.max(axis=0)])


def _collision_count(root: ET.Element, format: str) -> int:
    """How many collision geometries Drake's parser makes of ``root``."""
    plant = MultibodyPlant(0.0)
    scene_graph = SceneGraph()  # kept alive while the plant uses it
    plant.RegisterAsSourceForSceneGraph(scene_graph)
    Parser(plant).AddModelsFromString(ET.tostring(root, encoding="unicode"), format)
    plant.Finalize()
    return plant.num_collision_geometries()


def test_a_dae_visual_stands_in_drake_as_gazebo_shows_it():
    src = MESHES / "visual" / "link1.dae"
    gltf = drake_mesh(src, collision=False)
    assert gltf.suffix == ".gltf" and drake_mesh(src, collision=False) == gltf
    # Drake turns a glTF +90 deg about x; the converted scene is z-up as the .dae is
    expected = trimesh.load(src, force="mesh").bounds
    assert np.allclose(_hull_bounds(gltf), expected, atol=1e-6)
    assert np.allclose(_hull_bounds(drake_mesh(src, collision=True)), expected, atol=1e-6)


def test_stl_any_case_becomes_obj_and_obj_gltf_are_read_as_they_are(tmp_path):
    finger = drake_mesh(MESHES / "collision" / "finger.STL", collision=True)
    assert finger.suffix == ".obj"
    assert np.allclose(_hull_bounds(finger), trimesh.load(MESHES / "collision" / "finger.STL").bounds)
    obj = tmp_path / "part.obj"
    obj.write_text(trimesh.creation.box([0.1, 0.1, 0.1]).export(file_type="obj"))
    assert drake_mesh(obj, collision=True) == obj
    glb = tmp_path / "part.glb"
    glb.write_bytes(trimesh.creation.box([0.1, 0.2, 0.3]).export(file_type="glb"))
    gltf = drake_mesh(glb, collision=True)
    assert gltf.suffix == ".gltf"
    # as Drake reads any glTF: turned +90 deg about x (y-up to z-up)
    assert np.allclose(np.ptp(_hull_bounds(gltf), axis=0), [0.1, 0.3, 0.2])
    with pytest.raises(UnknownNameError, match=r"\.3ds.*\.stl"):
        drake_mesh(tmp_path / "part.3ds", collision=False)


def test_an_objs_bounds_are_trimeshs(tmp_path):
    """The box of the vertices its faces use (an unused vertex, relative indices, quads,
    v/vt/vn corners), as trimesh's bounds; a converted STL's too."""
    obj = tmp_path / "part.obj"
    obj.write_text(
        "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 -0.5 0.1 0.2 0.3\nvt 0 0\nvn 0 0 1\n"
        "f 2/1/1 3/1/1 4/1/1 5/1/1\nv 0.5 1 3\nf -1 -3 -4\n"
    )
    expected = trimesh.load(obj, force="mesh").bounds
    np.testing.assert_array_equal(obj_bounds(obj), expected)
    np.testing.assert_array_equal(expected, [[0, 0, -0.5], [1, 2, 3]])
    finger = drake_mesh(MESHES / "collision" / "finger.STL", collision=True)
    np.testing.assert_array_equal(obj_bounds(finger), trimesh.load(finger, force="mesh").bounds)
    obj.write_text("v 0 0 0\nv 1 0 0\n")
    with pytest.raises(ConfigError, match="part.obj: the mesh has no faces"):
        obj_bounds(obj)


def test_a_collada_unit_is_applied(tmp_path):
    text = (MESHES / "visual" / "hand.dae").read_text()
    cm = tmp_path / "hand_cm.dae"
    cm.write_text(text.replace("<asset>", '<asset><unit meter="0.01" name="centimeter"/>', 1))
    bounds = trimesh.load(MESHES / "visual" / "hand.dae", force="mesh").bounds
    assert np.allclose(_hull_bounds(drake_mesh(cm, collision=True)), bounds * 0.01, atol=1e-7)


URDF = """<robot name="r" xmlns:drake="http://drake.mit.edu"><link name="base">
  <visual><geometry><mesh filename="package://nobody/meshes/base.stl"/></geometry></visual>
  <visual><geometry><mesh filename="meshes/visual/hand.dae" scale="2 2 2"/></geometry></visual>
  <collision><geometry><mesh filename="file://meshes/collision/hand.stl"/></geometry></collision>
  <collision><geometry><mesh filename="meshes/collision/gone.stl"/></geometry></collision>
  <visual><geometry><mesh filename="package://fr7_description/package.xml"/></geometry></visual>
  <collision><geometry><mesh filename="package://fr7_description/meshes/collision/link0.stl"/></geometry>
    <drake:proximity_properties><drake:rigid_hydroelastic/></drake:proximity_properties></collision>
  <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
</link></robot>"""


def test_uris_resolve_and_a_missing_mesh_is_left_out_with_one_warning(caplog):
    root = ET.fromstring(URDF)
    packages = {"fr7_description": str(MESHES.parent)}
    with caplog.at_level(logging.WARNING, logger="omtp_drake.assets"):
        drake_ready_meshes(root, file=str(MESHES.parent / "robot.urdf"), packages=packages)
    warnings = [r.getMessage() for r in caplog.records]
    assert len(warnings) == 3
    assert "'package://nobody/meshes/base.stl'" in warnings[0] and str(MESHES.parent.parent) in warnings[0]
    assert "'meshes/collision/gone.stl'" in warnings[1] and str(MESHES / "collision") in warnings[1]
    assert "package.xml' is a .xml file (meshes: .stl, .dae, .obj, .gltf, .glb)" in warnings[2]
    link = root.find("link")
    (visual, box) = link.findall("visual")
    assert box.find("geometry/box") is not None
    assert visual.find("geometry/mesh").get("scale") == "2 2 2"
    (convex, hydro) = link.findall("collision")
    assert convex.find(f"geometry/mesh/{DRAKE}declare_convex") is not None
    assert hydro.find(f"geometry/mesh/{DRAKE}declare_convex") is None
    for mesh in link.iter("mesh"):
        assert mesh.get("filename").startswith("file:///") and Path(mesh.get("filename")[7:]).is_file()
    assert _collision_count(root, "urdf") == 2


def test_an_sdf_model_uri_becomes_the_converted_file(tmp_path):
    sdf = ET.fromstring(
        '<sdf version="1.7"><model name="m"><static>true</static><link name="l">'
        '<visual name="v"><geometry><mesh><uri>model://fr7_description/meshes/visual/link0.dae</uri>'
        "<scale>0.5 0.5 0.5</scale></mesh></geometry></visual>"
        '<collision name="c"><geometry><mesh><uri>model://fr7_description/meshes/collision/link0.stl</uri>'
        "</mesh></geometry></collision></link></model></sdf>"
    )
    drake_ready_meshes(
        sdf, file=str(tmp_path / "model.sdf"), packages={"fr7_description": str(MESHES.parent)}
    )
    uris = [u.text for u in sdf.iter("uri")]
    assert [Path(u).suffix for u in uris] == [".gltf", ".obj"]
    assert _collision_count(sdf, "sdf") == 1


def test_a_ur_links_collision_hull_is_within_its_tolerance_of_drakes_hull_with_fewer_vertices():
    """ur_arms.convex_hull_file: the kept vertices are Drake's hull's own, every vertex of that
    hull lies within HULL_TOLERANCE of the kept ones' hull (and one lies farther from a hull of
    a stricter tolerance, so the tolerance is what decides), and Drake reads the file as it is."""
    from scipy.spatial import ConvexHull

    from omtp_drake.ur_arms import HULL_TOLERANCE, _fewer_vertices, convex_hull_file, ur_description_dir

    src = ur_description_dir() / "meshes" / "ur10" / "collision" / "forearm.stl"
    exact = Mesh(str(drake_mesh(src, collision=True))).GetConvexHull()
    p_exact = np.array([exact.vertex(i) for i in range(exact.num_vertices())])
    kept = Mesh(str(convex_hull_file(drake_mesh(src, collision=True)))).GetConvexHull()
    p_kept = np.array([kept.vertex(i) for i in range(kept.num_vertices())])
    assert 4 <= len(p_kept) < len(p_exact)
    assert np.min(np.linalg.norm(p_kept[:, None] - p_exact[None], axis=2), axis=1).max() < 1e-9
    planes = ConvexHull(p_kept).equations
    outside = (p_exact @ planes[:, :3].T + planes[:, 3]).max(axis=1)
    assert outside.max() <= HULL_TOLERANCE + 1e-9
    stricter = len(_fewer_vertices(p_exact, HULL_TOLERANCE / 4))
    assert stricter > len(p_kept)
