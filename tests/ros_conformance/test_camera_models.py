"""The logical camera topics list what the course's plugin lists: every Gazebo model whose
bounding box meets the frustum (the conveyor, whose box is empty, always), named and
typed as the course's world names them
(omtp_gazebo/src/plugins/ROSLogicalCameraPlugin.cc, include/omtp_gazebo/plugins/ARIAC.hh,
Gazebo's LogicalCameraSensor; model names from worlds/omtp.world and the launch files'
spawn_model calls)."""

import pytest

from omtp_drake.cell.gazebo_models import gazebo_models, model_type
from omtp_drake.script import Cell

#: Every camera lists the conveyor first: its model has only nested models, so Gazebo's box
#: of it is empty and Gazebo 9's frustum test never rejects it; its nested models follow.
CONVEYOR = ["conveyor_belt", "conveyor_belt_fixed", "conveyor_belt_moving"]


@pytest.mark.parametrize(
    "name, expected",
    [
        ("object_3", "object"),
        ("object_12", "object"),
        ("bin_1_", "bin_1"),
        ("robot2", "robot2"),
        ("robot1_pedestal_", "robot1_pedestal"),
        ("workcell_", "workcell"),
        ("logical_camera_2", "logical_camera"),
        ("conveyor_belt", "conveyor_belt"),
        ("omtp|object_7", "object"),
        ("box_clone", "box"),
    ],
)
def test_model_type_is_arias_determine_model_type(name, expected):
    assert model_type(name) == expected


def test_the_cell_models_carry_the_course_world_names_in_its_order():
    with Cell("lecture6_assignment4", auto_spawn=False) as cell:
        models = gazebo_models(cell.station.plant, cell.scenario)
        names = [m.name for m in models]
        assert names[:4] == ["conveyor_belt", "deletion_wall", "logical_camera_1", "logical_camera_2"]
        assert names.index("break_beam_") < names.index("bin_1_") < names.index("workcell_")
        assert (
            names.index("workcell_") < names.index("robot1") < names.index("robot2") < names.index("object_1")
        )
        assert not any(n.startswith("vacuum_gripper") or n == "floor" for n in names)
        robot2 = next(m for m in models if m.name == "robot2")
        assert {cell.station.plant.GetModelInstanceName(i) for i in robot2.instances} == {
            "robot2",
            "vacuum_gripper2",
        }


def test_a_models_last_callback_never_fails_and_the_gripper_is_part_of_the_robot(course_run):
    report, data = course_run(
        "camera2_models_at_named_poses.py", scenario="lecture6_assignment4", out_arg=True, timeout=60
    )
    assert report.exception is None
    # The course's list is never empty (the conveyor and the workcell's box are always in view):
    # data.models[-1] raised in every callback at R2Place when it was.
    assert report.callback_errors == []
    assert data["callbacks"] > 50 and data["object_found"] is False
    for pose in ("R2PreGrasp", "R2Place"):
        assert data[pose]["types"] == [*CONVEYOR, "workcell", "robot2"]
        # tf: one frame per listed model, at the model's origin; none for the gripper.
        assert data[pose]["robot2_frame"] == pytest.approx([-7.8, -1.5, 0.7], abs=1e-6)
        assert data[pose]["workcell_frame"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-6)
        assert data[pose]["gripper_frame"] is None
        # The conveyor's model origin (omtp.world: its upstream end); no frame for nested models.
        assert data[pose]["conveyor_frame"] == pytest.approx([1.2, 5.0, 0.0], abs=1e-6)
        assert data[pose]["nested_frame"] is None


def test_a_spawned_part_is_the_last_model_and_the_cell_api_still_lists_parts_only(course_run):
    report, data = course_run(
        "camera2_part_is_last.py", scenario="lecture6_assignment4", out_arg=True, timeout=30
    )
    assert report.exception is None and report.callback_errors == []
    assert data["types"] == [*CONVEYOR, "workcell", "robot2", "object"]
    assert data["found"] >= 9
    # The part lies on the floor 1.8 m below camera 2 (its +x looks down): about 1.7 m along x.
    assert data["x"] == pytest.approx(1.7, abs=0.02)
    with Cell("lecture6_assignment4", auto_spawn=False) as cell:
        part = cell.spawn_part()
        cell.wait(2.0)
        assert list(cell.camera("logical_camera_2").parts()) == [part]


def test_the_lectures_single_camera_has_the_plugins_frame_for_the_part_it_lists(course_run):
    report, data = course_run(
        "single_camera_part_frame.py", scenario="lecture7_conveyor", out_arg=True, timeout=30
    )
    assert report.exception is None
    assert data["types"] == [*CONVEYOR, "workcell", "object"]
    # logical_camera_object_1_frame: the part's origin where the message puts it, in tf.
    assert data["in_camera"] == pytest.approx(data["message"], abs=1e-6)
    # The part waits at the beam (y = 1.9) on the belt (top 0.92, part centre 0.1 above).
    assert data["world"] == pytest.approx([1.2, 1.96, 1.021], abs=0.02)
