"""What a student hangs on a course arm is loaded as written and moves with the arm: the
group's workspace (tests/fixtures/group_ws) with their robot_system xacro holding a camera
bracket, a camera and its optical frame on robot 1's wrist (tests/fixtures/wrist_camera_edits,
the course's layout; spawn_robots.launch turns it on for robot 1 only; the camera's links are
named with the arm's prefix, as students name them, and are still theirs). The links are bodies
welded to the cell's ``robot1_wrist_3_link`` where xacro and the joint chain put them, their
mass on the arm, the Gazebo camera on them; the course's pick still works."""

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
from fixture_reports import assert_as_recorded

from omtp_drake.cli import main
from omtp_drake.launch import own_cell

FIXTURES = Path(__file__).resolve().parent / "fixtures"
STANDINS = Path(__file__).resolve().parent.parent / "omtp_drake" / "launch" / "standins"
LAUNCH = "omtp_lecture6 lecture6_assignment1.launch"
THEIRS = ("wrist_camera_bracket", "robot1_wrist_camera_link", "robot1_wrist_camera_optical")
JOINTS = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")
#: robot 1's spawn pose in their spawn_robots.launch (-x 0.5 -y 1.8 -z 0.95).
X_WM = np.eye(4)
X_WM[:3, 3] = [0.5, 1.8, 0.95]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    src = tmp_path_factory.mktemp("wrist_ws") / "src"
    shutil.copytree(FIXTURES / "group_ws" / "src", src)
    shutil.copytree(FIXTURES / "wrist_camera_edits", src, dirs_exist_ok=True)
    return src


@pytest.fixture(scope="module")
def cell(workspace):
    return own_cell(LAUNCH, workspace=[workspace], environ={})


@pytest.fixture(scope="module")
def urdf(workspace, tmp_path_factory) -> ET.Element:
    """Robot 1's URDF as xacro's own command line prints it (the launch's arguments;
    ``$(find)`` through an ament prefix written here by hand)."""
    prefix = tmp_path_factory.mktemp("ament")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    for package, folder in (
        ("omtp_support", workspace / "omtp_support"),
        ("ur_description", STANDINS / "ur_description"),
    ):
        (index / package).touch()
        (prefix / "share" / package).symlink_to(folder)
    xacro = Path(sys.executable).parent / "xacro"
    file = workspace / "omtp_support" / "urdf" / "robot_system" / "robot_system.xacro"
    args = [
        "robot_type:=ur10",
        "robot_prefix:=robot1_",
        "vacuum_gripper_prefix:=vacuum_gripper1_",
        "wrist_camera:=true",
    ]
    env = {**os.environ, "AMENT_PREFIX_PATH": str(prefix)}
    out = subprocess.run([str(xacro), str(file), *args], env=env, capture_output=True, text=True, check=True)
    return ET.fromstring(out.stdout)


def _rotation(axis, angle: float) -> np.ndarray:
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _rpy(r: float, p: float, y: float) -> np.ndarray:
    return _rotation([0, 0, 1], y) @ _rotation([0, 1, 0], p) @ _rotation([1, 0, 0], r)


def forward_kinematics(urdf: ET.Element, q: dict[str, float]) -> dict[str, np.ndarray]:
    """X_WL (4x4) of every link: the joints' origins and motions from ``world``, spawned at X_WM."""
    X = {"world": X_WM}
    joints = urdf.findall("joint")
    while len(X) < len(joints) + 1:
        for joint in joints:
            parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
            if parent in X and child not in X:
                origin = joint.find("origin")
                X_PJ = np.eye(4)
                if origin is not None:
                    X_PJ[:3, :3] = _rpy(*[float(v) for v in origin.get("rpy", "0 0 0").split()])
                    X_PJ[:3, 3] = [float(v) for v in origin.get("xyz", "0 0 0").split()]
                motion = np.eye(4)
                if joint.get("type") in ("revolute", "continuous"):
                    axis = joint.find("axis")
                    xyz = axis.get("xyz") if axis is not None else "1 0 0"
                    motion[:3, :3] = _rotation([float(v) for v in xyz.split()], q.get(joint.get("name"), 0.0))
                X[child] = X[parent] @ X_PJ @ motion
    return X


def test_their_links_on_the_wrist_are_a_model_hung_on_the_arm(cell):
    (mounted,) = [m for m in cell.scenario.models if m.parent.startswith("robot")]  # (not a camera's housing)
    assert mounted.parent == "robot1_wrist_3_link" and mounted.name == "wrist_camera_bracket"
    text = ET.fromstring(mounted.description)
    assert [link.get("name") for link in text.findall("link")] == list(THEIRS)
    assert [s.name for s in mounted.gazebo.sensors] == ["wrist_camera"]
    assert not [w for w in cell.warnings if "not loaded" in w or "wrist_camera" in w], cell.warnings
    # Robot 2 (the same xacro, without the argument) has none.
    assert [r.name for r in cell.scenario.robots] == ["robot1", "robot2"]


@pytest.fixture(scope="module")
def moved(cell):
    """The cell with robot 1 driven by its servo from Home to another pose (2 s)."""
    from omtp_drake.cell import arms
    from omtp_drake.sim.runtime import FactoryRuntime

    runtime = FactoryRuntime(cell.scenario, auto_spawn=False)
    station = runtime.station
    runtime.hold_arm("robot1", arms.named_pose("R1Home"))
    station.set_arm_locked(
        runtime.context, "robot1", False
    )  # (a held arm is locked: its servo drives it now)
    goal = np.array([0.9, -1.2, 1.4, -1.9, -1.2, 0.8])
    station.diagram.GetInputPort("robot1.position").FixValue(
        station.diagram.GetMyContextFromRoot(runtime.context), goal
    )
    runtime.advance_to(2.0)
    yield runtime, goal
    runtime.close()


def test_their_links_move_with_the_wrist_where_xacro_and_the_joint_chain_put_them(moved, urdf):
    runtime, goal = moved
    q_measured = runtime.joint_positions("robot1")
    np.testing.assert_allclose(q_measured, goal, atol=0.01)  # it moved there
    X = forward_kinematics(urdf, {f"robot1_{j}_joint": float(v) for j, v in zip(JOINTS, q_measured)})
    plant = runtime.station.plant
    context = plant.GetMyContextFromRoot(runtime.context)
    for link in (*THEIRS, "robot1_wrist_3_link", "robot1_tool0"):
        X_WL = plant.GetFrameByName(link).CalcPoseInWorld(context).GetAsMatrix4()
        np.testing.assert_allclose(X_WL[:3, 3], X[link][:3, 3], atol=1e-3, err_msg=link)
        assert np.abs(X_WL[:3, :3] - X[link][:3, :3]).max() < 1e-3, link
    # The Gazebo camera on their link looks out of its optical frame.
    from omtp_drake.cell.depth_camera import DepthCamera

    camera: DepthCamera = runtime.station.depth_cameras["wrist_camera"]
    X_WO = camera.pose.Eval(camera.pose.get_system().GetMyContextFromRoot(runtime.context))
    np.testing.assert_allclose(X_WO.GetAsMatrix4(), X["robot1_wrist_camera_optical"], atol=1e-3)


def test_their_links_weigh_on_the_arm(moved):
    runtime, _ = moved
    plant = runtime.station.plant
    body = plant.GetBodyByName("wrist_camera_bracket")
    assert plant.GetModelInstanceName(body.model_instance()) == "wrist_camera_bracket"
    context = plant.GetMyContextFromRoot(runtime.context)
    assert plant.CalcTotalMass(context, [body.model_instance()]) == pytest.approx(0.5)
    # It hangs on the wrist by a weld (the arm's dynamics carry it), not in the world.
    joint = next(
        plant.get_joint(j)
        for j in plant.GetJointIndices(body.model_instance())
        if plant.get_joint(j).child_body() == body
    )
    assert joint.parent_body().name() == "robot1_wrist_3_link" and joint.num_velocities() == 0


def test_their_links_are_part_of_robot_1s_gazebo_model(moved):
    from omtp_drake.cell.gazebo_models import gazebo_models

    runtime, _ = moved
    plant = runtime.station.plant
    models = {m.name: m for m in gazebo_models(plant, runtime.station.scenario)}
    bracket = plant.GetBodyByName("wrist_camera_bracket").model_instance()
    assert bracket in models["robot1"].instances and "wrist_camera_bracket" not in models


def test_tf_echo_and_frames_give_their_camera_where_the_arm_holds_it(
    workspace, urdf, moved, capsys, tmp_path
):
    """tf-echo through the command line (its own cell of their launch); the frame tree drawn
    from the module's cell (the ``frames`` command's drawing; that command's own run with a
    launch is test_docs_run's and test_cell_options')."""
    from omtp_drake.cell import arms
    from omtp_drake.sim.tf import TfBuffer
    from omtp_drake.viz.tree import view_frames

    q = arms.named_pose("R1PreGrasp")
    X = forward_kinematics(urdf, {f"robot1_{j}_joint": float(v) for j, v in zip(JOINTS, q)})
    argv = ["tf-echo", "--launch", LAUNCH, "--workspace", str(workspace), "--pose", "robot1=R1PreGrasp"]
    assert main([*argv, "world", "robot1_wrist_camera_optical", "--json"]) == 0, capsys.readouterr().err
    echoed = json.loads(capsys.readouterr().out)["translation"]
    np.testing.assert_allclose(echoed, X["robot1_wrist_camera_optical"][:3, 3], atol=1e-3)
    runtime, _ = moved
    buffer = TfBuffer.from_context(runtime.station, runtime.context)
    assert set(THEIRS) <= {child for _, child in buffer.edges(None)}  # (in the tree it draws)
    pdf, png = view_frames(buffer, tmp_path / "frames")
    assert pdf.suffix == ".pdf" and pdf.is_file() and png.is_file()


def test_the_frame_tree_hangs_their_links_on_the_wrist(moved):
    from omtp_drake.sim.tf import TfBuffer

    runtime, _ = moved
    buffer = TfBuffer.from_context(runtime.station, runtime.context)
    assert buffer.parent("wrist_camera_bracket") == "robot1_wrist_3_link"
    assert buffer.parent("robot1_wrist_camera_link") == "wrist_camera_bracket"


def test_their_view_of_robot_1_lists_their_links(workspace, capsys):
    argv = [
        "view",
        "--launch",
        LAUNCH,
        "--workspace",
        str(workspace),
        "--param",
        "/robot1/robot1_description",
    ]
    assert main([*argv, "--json"]) == 0, capsys.readouterr().err
    info = json.loads(capsys.readouterr().out)
    assert set(THEIRS) <= set(info["links"])


def test_their_belt_script_still_picks_with_the_camera_on_the_wrist(workspace, tmp_path):
    script = workspace / "omtp_lecture6" / "scripts" / "belt_to_bin_robot1.py"
    out = tmp_path / "report.json"
    argv = ["ros-run", str(script), "1", "--launch", LAUNCH, "--workspace", str(workspace)]
    assert main([*argv, "--timeout", "60", "--json", str(out), "-q"]) == 0
    report = json.loads(out.read_text())
    assert report["exception"] is None, report["traceback"]
    assert sum(report["ledger"]["in_bin"].values()) >= 1, report["ledger"]
    assert_as_recorded("wrist_camera_edits belt_to_bin_robot1.py 1", report)


def test_a_link_on_a_moving_joint_of_its_own_is_one_warning():
    from omtp_drake.launch.own_links import mounts, own_links
    from omtp_drake.launch.urdf_model import UrdfModel

    text = """<robot name="robot1">
      <link name="world"/>
      <link name="robot1_base_link"/>
      <link name="robot1_tool0"/>
      <link name="plate"><visual><geometry><box size="0.1 0.1 0.01"/></geometry></visual></link>
      <link name="flap"><visual><geometry><box size="0.1 0.1 0.01"/></geometry></visual></link>
      <joint name="base" type="fixed"><parent link="world"/><child link="robot1_base_link"/></joint>
      <joint name="pan" type="revolute"><parent link="robot1_base_link"/><child link="robot1_tool0"/>
        <axis xyz="0 0 1"/></joint>
      <joint name="plate" type="fixed"><parent link="robot1_tool0"/><child link="plate"/>
        <origin xyz="0 0 0.1" rpy="0 0 0.2"/></joint>
      <joint name="hinge" type="revolute"><parent link="plate"/><child link="flap"/>
        <axis xyz="1 0 0"/></joint>
    </robot>"""
    model = UrdfModel.from_text(text, "arm.urdf")
    (mount,) = mounts(model, ["robot1_"])
    assert (mount.root, mount.parent, mount.links) == ("plate", "robot1_tool0", ("plate",))
    np.testing.assert_allclose(mount.X_PR.translation(), [0, 0, 0.1])
    assert own_links(model, ["robot1_"], "arm.urdf") == (
        [],
        [
            "arm.urdf: link 'flap' moves on a joint of its own ('hinge'); not loaded "
            "(the cell adds no joints to the course's pieces)"
        ],
    )
