"""The scripting layer (omtp_drake.script): moves, guards, errors, tf and the services."""

import numpy as np
import pytest
from pydrake.math import RigidTransform

from omtp_drake import Cell, tool_down
from omtp_drake.cell import arms
from omtp_drake.cell.suction import contact_points
from omtp_drake.errors import (
    CollisionError,
    ConfigError,
    FrameError,
    GoalInCollisionError,
    PlanningError,
    StateError,
    UnknownNameError,
    UnreachableError,
)
from omtp_drake.ur_arms import model_rates

#: Cup face inside bin 1 (rim at 0.475 m), and just outside its wall toward robot 2.
P_IN_BIN = [-8.0, -2.2, 0.35]
P_OUTSIDE_WALL = [-8.0, -1.85, 0.30]


@pytest.fixture(scope="module")
def cell():
    """Assignment 4's cell, no automatic spawns; tests leave its arm where they like."""
    return Cell("lecture6_assignment4", auto_spawn=False)


def test_named_pose_move_ends_within_1_mrad(cell):
    arm = cell.arm("robot2")
    for name in ("Place", "Home"):
        result = arm.go(name)
        error = np.abs(arm.joint_values() - arms.named_pose(name, arm.config)).max()
        assert error < 1e-3, (name, error)
        assert result.end > result.start and not result.stopped


def test_cartesian_line_stays_on_the_line_within_the_limits(cell):
    arm = cell.arm("robot2")
    arm.go("Home")
    start = arm.tool_pose()
    goal = RigidTransform(start.rotation(), start.translation() + [0.15, -0.1, -0.3])
    plan = arm.compute_cartesian_path(goal, speed=0.3)
    assert plan.fraction == 1.0
    # The planned joint velocities, sampled every millisecond, stay within the UR5's limits.
    limits = np.array(model_rates("ur5")[0])
    times = np.arange(0.0, plan.duration, 1e-3)
    v = np.array([plan.trajectory.EvalDerivative(t, 1).ravel() for t in times])
    assert np.all(np.abs(v) <= limits + 1e-6)
    # The cup face, logged every 10 ms while the move runs, stays within 2 mm of the line.
    a, b = start.translation(), goal.translation()
    log = []

    def record() -> bool:
        log.append((arm.tool_pose().translation(), arm.joint_values()))
        return False

    arm.execute(plan, until=record)
    u = (b - a) / np.linalg.norm(b - a)
    off_line = [np.linalg.norm((p - a) - ((p - a) @ u) * u) for p, _ in log]
    assert len(log) > 20 and max(off_line) < 2e-3
    assert np.linalg.norm(arm.tool_pose().translation() - b) < 2e-3
    steps = np.diff(np.array([q for _, q in log]), axis=0) / 0.01  # measured joint speeds
    assert np.all(np.abs(steps) <= limits * 1.02)


def test_guarded_descent_stops_at_the_part_with_it_attached(cell):
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    arm.go("Home")
    part = cell.spawn_part()
    cell.wait(1.5)
    seen = cell.camera("logical_camera_2").image().pose_of(part)
    p = cell.tf.transform_pose(seen, "world").pose.translation()
    np.testing.assert_allclose(p, cell.part_pose(part).translation(), atol=2e-3)
    arm.move_to(tool_down(p + [0, 0, 0.2]))
    vacuum.on()
    first_contact = []

    def attached() -> bool:
        if not first_contact and vacuum.state().enabled and _cup_touches(cell, part):
            first_contact.append(arm.tool_pose().translation())
        return vacuum.attached

    result = arm.move_linear(tool_down(p + [0, 0, 0.0]), speed=0.05, until=attached)
    assert result.stopped and vacuum.attached and vacuum.part == part
    assert first_contact
    assert np.linalg.norm(arm.tool_pose().translation() - first_contact[0]) < 5e-3
    # Lift it, put it back down, let go.
    arm.move_linear(tool_down(p + [0, 0, 0.3]))
    assert cell.part_pose(part).translation()[2] > 0.29  # lifted with the cup (0.1 below it)
    vacuum.off()
    cell.wait(1.0)
    assert cell.ledger().parts[part] == "on_floor"
    cell.remove_part(part)


def _cup_touches(cell, part) -> bool:
    plant = cell.station.plant
    cup, body = plant.GetBodyByName("vacuum_gripper2_cup").index(), plant.GetBodyByName(part).index()
    return contact_points(plant, plant.GetMyContextFromRoot(cell.runtime.context), cup, body) > 0


def test_joint_move_goes_around_the_bin_wall(cell):
    """From inside bin 1 to the other side of its wall: the straight joint path would hit
    the wall; the planned one does not touch the bin at any time."""
    arm = cell.arm("robot2")
    arm.go("Place")
    arm.move_to(tool_down(P_IN_BIN))
    q_in = arm.joint_values()
    q_out = arm.planner.ik(tool_down(P_OUTSIDE_WALL), q_seed=q_in)
    assert any("bin_1" in pair[1] for pair in arm.planner.path_collisions(q_in, q_out))
    touches = []

    def watch() -> bool:
        touches.extend(pair for pair in arm.contacts() if "bin" in pair[1])
        return False

    plan = arm.plan(q_out)
    assert len(plan.path) > 2  # not the straight segment
    arm.execute(plan, until=watch)
    assert touches == []
    assert np.abs(arm.joint_values() - q_out).max() < 1e-3


def test_a_part_in_the_planning_scene_refuses_the_line_and_one_put_there_later_stops_the_arm(cell):
    """Beside a part on the floor, the gripper's body (not its cup) would reach below the
    part's top. Loose parts are no obstacles (MoveIt's planning scene): the line plans.
    With the part added to the planning scene, the line is refused before anything
    moves; planned first and the part put there (and added) after, the arm stops on
    touching it with a CollisionError naming both bodies, and stays there."""
    arm = cell.arm("robot2")
    spot = [-8.3, -1.23, 0.3]  # under logical camera 2, where the course drops parts
    part = cell.spawn_part(xyz=spot, yaw=0.0)
    try:
        cell.wait(1.0)
        p = cell.part_pose(part).translation()  # a 0.2 m cube: its top at p_z + 0.1
        above, down = tool_down(p + [0.125, 0.0, 0.3]), tool_down(p + [0.125, 0.0, -0.05])
        arm.move_to(above)
        assert arm.compute_cartesian_path(down).fraction == 1.0  # not in the scene: no obstacle
        cell.planning_scene.add_part(part)
        with pytest.raises(PlanningError, match=r"only \d+ % of the straight-line motion"):
            arm.move_linear(down)
        plan, fraction = arm.compute_cartesian_path(down, 0.005, 0.5)  # MoveIt's call shape
        assert 0.0 < fraction < 1.0 and plan.fraction == fraction
        assert np.linalg.norm(arm.tool_pose().translation() - above.translation()) < 2e-3
        cell.remove_part(part)
        cell.planning_scene.remove(part)
        plan = arm.compute_cartesian_path(down)
        assert plan.fraction == 1.0
        part = cell.spawn_part(xyz=spot, yaw=0.0)
        cell.wait(1.0)
        cell.planning_scene.add_part(part)
        with pytest.raises(CollisionError, match=f"touched something it should not: "
                                                 f"vacuum_gripper2_base_link - {part}; it stopped there"):
            arm.execute(plan)
        stopped = arm.tool_pose().translation()
        assert stopped[2] + 0.015 > p[2] + 0.1 - 0.01  # its body (cup face + 15 mm) within 1 cm of the top
        cell.wait(0.5)
        assert np.linalg.norm(arm.tool_pose().translation() - stopped) < 2e-3
        assert arm.contacts() == [("vacuum_gripper2_base_link", part)]
    finally:
        cell.remove_part(part)
        cell.planning_scene.remove()
    arm.go("Home")


def test_a_box_held_by_a_gripper_is_detached_before_it_is_replaced(cell):
    scene = cell.planning_scene
    scene.attach_box("robot2", "held_box", size=0.1)
    try:
        with pytest.raises(StateError, match="'held_box' is attached to robot2; detach it first"):
            scene.add_box("held_box", RigidTransform([-8.0, -1.5, 0.5]), 0.1)
        scene.detach("robot2", "held_box")
        scene.add_box("held_box", RigidTransform([-8.0, -1.5, 0.5]), 0.1)  # in the world now: replaced
    finally:
        scene.detach()
        scene.remove()


def test_execute_without_wait_moves_two_arms_at_once(cell):
    """Robot 1's move started with wait=False runs while robot 2's blocking move does:
    both arrive, in the time of the longer one; a guard without waiting is refused."""
    arm1, arm2 = cell.arm("robot1"), cell.arm("robot2")
    arm2.go("Home")
    plan1, plan2 = arm1.plan("PreGrasp"), arm2.plan("PreGrasp")
    start = cell.time
    started = arm1.execute(plan1, wait=False)
    assert started.start == start and started.end == pytest.approx(start + plan1.duration)
    assert cell.time == start  # returned at once
    arm2.execute(plan2)
    cell.wait(max(0.0, started.end - cell.time) + 0.3)
    for arm in (arm1, arm2):
        assert np.abs(arm.joint_values() - arms.named_pose("PreGrasp", arm.config)).max() < 1e-3
    assert cell.time - start < plan1.duration + plan2.duration
    with pytest.raises(ConfigError, match="a guard \\(until\\) needs wait=True"):
        arm1.execute(arm1.plan("Home"), until=lambda: True, wait=False)
    arm1.go("Home")


@pytest.mark.parametrize("target, error, words", [
    (tool_down([-8.0, 0.5, 0.5]), UnreachableError, ["unreachable"]),
    ([0.0, 0.0, 4.0, 0.0, 0.0, 0.0], UnreachableError, ["elbow_joint", "outside its limits"]),
    ([1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0.0, 0.0], ConfigError, ["6 numbers"]),
    ("R1Home", UnknownNameError, ["unknown named pose of robot2 'R1Home'", "R2Home"]),
])
def test_impossible_moves_are_clear_errors_and_nothing_moves(cell, target, error, words):
    arm = cell.arm("robot2")
    arm.go("Home")
    t, q = cell.time, arm.joint_values()
    with pytest.raises(error) as e:
        arm.go(target)
    for word in words:
        assert word in str(e.value)
    assert cell.time == t and np.array_equal(arm.joint_values(), q)


def test_a_goal_inside_the_bin_wall_is_refused_naming_the_bodies(cell):
    arm = cell.arm("robot2")
    arm.go("Home")
    t = cell.time
    q_wall = arm.planner.ik(tool_down([-8.0, -2.0, 0.30]), q_seed=arm.joint_values(),
                            check_collisions=False)  # the cup in bin 1's wall
    with pytest.raises(GoalInCollisionError, match="in collision.*bin_1"):
        arm.go(q_wall)
    assert cell.time == t


def test_straight_line_out_of_reach_is_refused():
    cell = Cell("omtp_factory")
    arm = cell.arm("robot2")
    start = arm.tool_pose()
    far = RigidTransform(start.rotation(), start.translation() + [0.0, 0.0, -1.5])  # through the floor
    plan = arm.compute_cartesian_path(far)
    assert 0.0 <= plan.fraction < 1.0
    with pytest.raises(PlanningError, match=r"only \d+ % of the straight-line motion"):
        arm.move_linear(far)
    assert cell.time == 0.0


def test_tf_buffer_records_by_itself_so_image_time_lookups_work():
    cell = Cell("lecture6_assignment3")
    cell.wait(1.5)
    image = cell.camera("logical_camera_2").image()
    assert image.time < cell.time  # an older image: the buffer has its time
    X = cell.tf.transform_pose(image.pose_of("object_1"), "world")
    assert X.time == image.time
    np.testing.assert_allclose(X.pose.translation(), cell.part_pose("object_1").translation(), atol=2e-3)
    with pytest.raises(FrameError, match="logical_camera_2 does not see 'object_7'"):
        image.pose_of("object_7")


def test_a_part_the_camera_does_not_see_is_a_frame_error_naming_the_camera():
    cell = Cell("lecture6_assignment3")
    cell.wait(1.5)
    with pytest.raises(FrameError, match="logical_camera_1 has not seen .object_1. .*show nothing"):
        cell.tf.lookup_transform("world", "logical_camera_1_object_1_frame")


def test_services_validate_their_arguments():
    cell = Cell("lecture6_assignment4", auto_spawn=False)
    rt = cell.runtime
    for bad in (-3, float("nan"), float("inf"), "soon"):
        with pytest.raises(ConfigError, match="black_out_camera duration"):
            rt.black_out_camera("logical_camera_2", bad)
        with pytest.raises(ConfigError, match="fail_vacuum duration"):
            rt.fail_vacuum("robot2", bad)
    with pytest.raises(UnknownNameError, match="closest: logical_camera_2"):
        cell.camera("logical_camera2")
    with pytest.raises(ConfigError, match="6 numbers"):
        rt.hold_arm("robot1", [0.0] * 5)
    with pytest.raises(ConfigError, match="outside the cell"):
        cell.spawn_part([0.0, 0.0, -5.0])
