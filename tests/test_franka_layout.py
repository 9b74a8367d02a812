"""A robot from another ROS description package: ``tests/fixtures/franka_ws`` holds a 7-joint
arm with a two-finger hand in franka_description's layout (xacro macros, ``.stl`` collision
and ``.dae`` visual meshes, ``<ros2_control>`` with ``xacro.load_yaml`` of its initial
positions) on a pedestal beside a conveyor module (a ``.dae`` in millimetres, scaled).

It loads as it is: ``view --json`` lists every joint; each link's frame is where an
independent expansion (xacro's own command line on an ament prefix written here) and a
joint chain in numpy put it; the meshes are converted once and taken from the cache after.
"""

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import yaml
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from omtp_drake import assets
from omtp_drake.cell.described_models import add_described_models, prepared_description
from omtp_drake.cli import main
from omtp_drake.scenario.models import file_workspace, model_from_file

SRC = Path(__file__).parent / "fixtures" / "franka_ws" / "src"
CELL = SRC / "fr7_cell" / "urdf" / "fr7_cell.urdf.xacro"
INITIAL = SRC / "fr7_description" / "config" / "initial_positions.yaml"
FINGER = 0.015


@pytest.fixture(scope="module")
def independent_urdf(tmp_path_factory) -> ET.Element:
    """The cell expanded by xacro's own command line, ``$(find)`` through an ament prefix
    written here by hand (not by the code under test)."""
    prefix = tmp_path_factory.mktemp("ament")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    for package in ("fr7_description", "fr7_cell"):
        (index / package).touch()
        (prefix / "share" / package).symlink_to(SRC / package)
    xacro = Path(sys.executable).parent / "xacro"
    env = {**os.environ, "AMENT_PREFIX_PATH": str(prefix)}
    out = subprocess.run([str(xacro), str(CELL)], env=env, capture_output=True, text=True, check=True)
    return ET.fromstring(out.stdout)


@pytest.fixture(scope="module")
def model():
    return model_from_file(CELL, file_workspace(CELL, [SRC]), static=True)


def _positions() -> dict[str, float]:
    initial = yaml.safe_load(INITIAL.read_text())["initial_positions"]
    q = {f"fr7_{name}": float(value) for name, value in initial.items()}
    return {**q, "fr7_finger_joint_left": FINGER, "fr7_finger_joint_right": FINGER}


def _rpy(r: float, p: float, y: float) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def _axis_angle(axis: np.ndarray, angle: float) -> np.ndarray:
    k = axis / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _chain(urdf: ET.Element, q: dict[str, float]) -> dict[str, np.ndarray]:
    """X_WL (4x4) of every link from the URDF's joints, ``world`` at the identity."""
    X = {"world": np.eye(4)}
    joints = urdf.findall("joint")
    while len(X) < len(joints) + 1:
        for joint in joints:
            parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
            if parent not in X or child in X:
                continue
            origin = joint.find("origin")
            xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()]
            rpy = [float(v) for v in origin.get("rpy", "0 0 0").split()]
            X_PJ = np.eye(4)
            X_PJ[:3, :3], X_PJ[:3, 3] = _rpy(*rpy), xyz
            axis = np.array(
                [
                    float(v)
                    for v in (
                        joint.find("axis").get("xyz") if joint.find("axis") is not None else "1 0 0"
                    ).split()
                ]
            )
            X_JC = np.eye(4)
            if joint.get("type") == "revolute":
                X_JC[:3, :3] = _axis_angle(axis, q[joint.get("name")])
            elif joint.get("type") == "prismatic":
                X_JC[:3, 3] = axis / np.linalg.norm(axis) * q[joint.get("name")]
            X[child] = X[parent] @ X_PJ @ X_JC
    return X


def test_view_json_lists_every_joint(independent_urdf, tmp_path):
    out = tmp_path / "fr7.json"
    assert main(["view", str(CELL), "--workspace", str(SRC), "--json", str(out)]) == 0
    listed = json.loads(out.read_text())
    expected = {j.get("name"): j.get("type") for j in independent_urdf.findall("joint")}
    assert {j["name"]: j["type"] for j in listed["joints"]} == expected
    assert len([t for t in expected.values() if t == "revolute"]) == 7
    assert {j.get("name") for j in independent_urdf.findall("link")} - {"world"} == set(listed["links"])


def test_every_link_frame_is_where_xacro_and_the_joint_chain_put_it(independent_urdf, model):
    plant = MultibodyPlant(0.0)
    (instance,) = add_described_models(Parser(plant), [model], gazebo_look=False).values()
    q = _positions()
    for name, value in q.items():
        plant.GetJointByName(name, instance).set_default_positions([value])
    plant.Finalize()
    context = plant.CreateDefaultContext()
    expected = _chain(independent_urdf, q)
    assert len(expected) == 16
    for link, X_WL in expected.items():
        if link == "world":
            continue
        X = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(link, instance))
        assert np.linalg.norm(X.translation() - X_WL[:3, 3]) < 1e-3, link
        assert np.abs(X.rotation().matrix() - X_WL[:3, :3]).max() < 1e-3, link


def test_the_meshes_are_converted_once_then_taken_from_the_cache(model, tmp_path, monkeypatch):
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path))
    converted: list[tuple[Path, Path]] = []
    convert = assets.convert_mesh

    def counting(src: Path, dst: Path) -> None:
        converted.append((src, dst))
        convert(src, dst)

    monkeypatch.setattr(assets, "convert_mesh", counting)
    first = prepared_description(model, gazebo_look=False)
    # 10 .dae visuals -> .gltf, 10 .stl collisions -> .obj, the conveyor's .dae as both
    assert sorted(dst.suffix for _, dst in converted) == [".gltf"] * 11 + [".obj"] * 11
    assert {src.suffix for src, _ in converted} == {".dae", ".stl", ".DAE", ".STL"}
    converted.clear()
    second = prepared_description(model, gazebo_look=False)
    assert converted == [] and second == first
    uris = [m.get("filename") for m in ET.fromstring(second).iter("mesh")]
    assert len(uris) == 24 and all(u.startswith(f"file://{tmp_path}/") for u in uris)


def test_the_arm_stands_in_a_cell_and_says_what_needs_a_ur(independent_urdf):
    from omtp_drake.errors import NotSupportedError
    from omtp_drake.script import Cell

    cell = Cell(robot=CELL, workspace=[SRC])
    try:
        cell.wait(0.05)
        X_WB = cell.tf.lookup_transform("world", "fr7_link0", 0).transform
        expected = _chain(independent_urdf, _positions())["fr7_link0"]
        assert np.allclose(X_WB.GetAsMatrix4(), expected, atol=1e-3)
        with pytest.raises(NotSupportedError, match="UR arms"):
            cell.arm("fr7_cell")
    finally:
        cell.close()
