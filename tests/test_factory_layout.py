"""The factory scene sits at the course's reference poses (omtp_factory.md sections 1-3)."""

import math

import numpy as np
import pytest
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.cell import arms
from omtp_drake.cell.frames import FrameTree

# Reference layout table: frame -> (xyz, rpy or None when only the position is given).
LAYOUT = {
    "robot1_pedestal_link": ((0.5, 1.8, 0.0), (0, 0, 0)),
    "robot1_base_link": ((0.5, 1.8, 0.95), (0, 0, 0)),
    # The course's robot_pedestal macro places the pedestal without the arm's yaw.
    "robot2_pedestal_link": ((-7.8, -1.5, 0.0), (0, 0, 0)),
    "robot2_base_link": ((-7.8, -1.5, 0.70), (0, 0, 1.57)),
    "bin_1_base_link": ((-8.0, -2.2, 0.0), (0, 0, 0)),
    "bin_1_drop_point": ((-8.0, -2.2, 1.0), (0, 0, 0)),
    "logical_camera_1_frame": ((1.2, 1.8, 2.0), (0, 1.5708, 0)),
    "logical_camera_2_frame": ((-8.3, -1.23, 1.8), (0, 1.5708, 0)),
    "break_beam_base_link": ((1.6, 1.9, 0.925), (0, 0, math.pi)),
    "break_beam_optical_link": ((1.575, 1.9, 0.925), None),
    "deletion_wall": ((1.2, -5.1, 1.425), (0, 0, 1.5708)),
}

# Suction-cup frame in world at each named pose (reference section 3, +/- 1 mm).
SUCTION = {
    "R1Up": (0.500, 2.066, 2.377), "R1Home": (0.336, 2.488, 1.587),
    "R1PreGrasp": (0.871, 2.402, 1.587), "R1Place": (0.664, 1.112, 1.587),
    "R2Up": (-8.001, -1.500, 1.701), "R2Home": (-8.287, -1.609, 1.122),
    "R2PreGrasp": (-8.221, -1.233, 1.122), "R2Place": (-8.035, -2.095, 1.250),
}


@pytest.fixture(scope="module")
def tree(factory):
    return FrameTree(factory.plant)


def _pose(factory, tree, target, source, positions=None):
    context = factory.create_context(positions)
    return tree.lookup_transform(factory.plant.GetMyContextFromRoot(context), target, source)


@pytest.mark.parametrize("name", sorted(LAYOUT))
def test_layout_frame_at_reference_pose(factory, tree, name):
    xyz, rpy = LAYOUT[name]
    X = _pose(factory, tree, "world", name)
    np.testing.assert_allclose(X.translation(), xyz, atol=1e-3)
    if rpy is not None:
        R_err = X.rotation().inverse() @ RollPitchYaw(rpy).ToRotationMatrix()
        angle = math.degrees(R_err.ToAngleAxis().angle())
        assert angle < 0.1, f"{name} off by {angle:.3f} deg"


def test_break_beam_points_along_world_minus_x(factory, tree):
    X = _pose(factory, tree, "world", "break_beam_optical_link")
    np.testing.assert_allclose(X.rotation().col(0), [-1, 0, 0], atol=1e-9)


def test_belt_top_surface_height(factory):
    plant = factory.plant
    context = plant.CreateDefaultContext()
    belt = plant.GetBodyByName("conveyor_belt")
    X_WB = plant.EvalBodyPoseInWorld(context, belt)
    assert X_WB.translation()[2] == pytest.approx(0.920, abs=1e-9)
    assert X_WB.translation()[0] == pytest.approx(1.2, abs=1e-9)


@pytest.mark.parametrize("pose", sorted(SUCTION))
def test_suction_cup_at_named_pose(factory, tree, pose):
    robot = "robot1" if pose.startswith("R1") else "robot2"
    X = _pose(factory, tree, "world", f"vacuum_gripper{robot[-1]}_suction_cup",
              {robot: arms.named_pose(pose)})
    np.testing.assert_allclose(X.translation(), SUCTION[pose], atol=1e-3)


def test_suction_cup_and_tip_offsets_on_tool0(factory, tree):
    for n in (1, 2):
        X = _pose(factory, tree, f"robot{n}_tool0", f"vacuum_gripper{n}_suction_cup")
        np.testing.assert_allclose(X.GetAsMatrix4(), RigidTransform([0, 0, 0.01]).GetAsMatrix4(), atol=1e-12)
        X = _pose(factory, tree, f"robot{n}_tool0", f"vacuum_gripper{n}_tip")
        np.testing.assert_allclose(X.translation(), [0, 0, 0.0775], atol=1e-12)


@pytest.mark.parametrize("robot, expected, tol", [
    ("robot1", (-8.50, -4.00, -0.95), 1e-3),
    ("robot2", (-0.70, 0.20, -0.70), 2e-3),
])
def test_bin_in_robot_base_frame(factory, tree, robot, expected, tol):
    X = _pose(factory, tree, f"{robot}_base_link", "bin_1_base_link")
    np.testing.assert_allclose(X.translation(), expected, atol=tol)


def test_frame_tree_names_and_edges(tree):
    names = set(tree.names())
    for n in (1, 2):
        chain = ["pedestal_link", "base_link", "shoulder_link", "upper_arm_link", "forearm_link",
                 "wrist_1_link", "wrist_2_link", "wrist_3_link", "tool0"]
        assert {f"robot{n}_{c}" for c in chain} <= names
        assert {f"vacuum_gripper{n}_base_link", f"vacuum_gripper{n}_suction_cup"} <= names
    assert tree.parent("vacuum_gripper1_base_link") == "robot1_tool0"
    assert tree.parent("vacuum_gripper1_suction_cup") == "vacuum_gripper1_base_link"
    assert tree.parent("robot1_base_link") == "world"
    assert tree.parent("bin_1_drop_point") == "bin_1_base_link"
    assert tree.parent("world") is None
    assert not any(n.endswith("_joint_parent") for n in names)


def test_unknown_frame_lists_closest(tree):
    from omtp_drake.errors import UnknownNameError

    with pytest.raises(UnknownNameError, match="robot1_tool0"):
        tree.frame("robot1_tol0")
