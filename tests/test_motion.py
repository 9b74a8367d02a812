"""Motion planning for one arm (omtp_drake.control.motion): collisions, planning, IK,
Cartesian paths and time parameterization, for robot 2 (a UR5) next to bin 1."""

import dataclasses
import itertools

import numpy as np
import pytest
from pydrake.math import RigidTransform, RollPitchYaw, RotationMatrix

from omtp_drake.cell import arms
from omtp_drake.control.motion import ArmPlanner
from omtp_drake.errors import GoalInCollisionError, PlanningError, StartInCollisionError, UnreachableError
from omtp_drake.scenario import load_scenario

DOWN = RotationMatrix(RollPitchYaw(np.pi, 0.0, 0.0))  # tool +z pointing down
#: Tip 0.35 m above the floor at bin 1's centre: inside the bin (rim at 0.475).
P_IN_BIN = [-8.0, -2.2, 0.35]
#: Tip 0.30 m above the floor just outside bin 1's wall that faces robot 2 (y = -2.0).
P_OUTSIDE_WALL = [-8.0, -1.85, 0.30]


@pytest.fixture(scope="module")
def scenario():
    return load_scenario("lecture6_assignment4")


@pytest.fixture(scope="module")
def planner(scenario):
    return ArmPlanner(scenario, "robot2")


@pytest.fixture(scope="module")
def over_the_wall(planner):
    """(q in the bin, q outside its wall, the planned path between them)."""
    q_in = planner.ik(RigidTransform(DOWN, P_IN_BIN), q_seed=arms.named_pose("R2Place"))
    q_out = planner.ik(RigidTransform(DOWN, P_OUTSIDE_WALL), q_seed=q_in)
    return q_in, q_out, planner.plan(q_in, q_out)


def straight(a, b, step):
    n = max(1, int(np.ceil(np.linalg.norm(b - a) / step)))
    return [a + s * (b - a) for s in np.linspace(0.0, 1.0, n + 1)]


def test_named_poses_are_collision_free(planner):
    for name in ("Home", "Up", "PreGrasp", "Place"):
        assert planner.collisions(arms.named_pose(name, planner.robot)) == [], name


def test_ik_puts_the_tool_at_the_pose(planner, over_the_wall):
    q_in, q_out, _ = over_the_wall
    for q, p in ((q_in, P_IN_BIN), (q_out, P_OUTSIDE_WALL)):
        X_WE = planner.forward_kinematics(q, "tip")
        assert np.linalg.norm(X_WE.translation() - p) < 2e-4
        assert X_WE.rotation().InvertAndCompose(DOWN).ToAngleAxis().angle() < 2e-3
    lower, upper = planner.joint_limits
    assert np.all(q_in >= lower) and np.all(q_in <= upper)
    # The course's frame: 1 cm off the flange, 67.5 mm behind the tip.
    X_WS = planner.forward_kinematics(q_in, "suction_cup")
    assert np.allclose(X_WS.translation(), np.array(P_IN_BIN) + [0, 0, 0.0675], atol=3e-4)


def test_plan_goes_over_the_bin_wall(planner, over_the_wall):
    q_in, q_out, path = over_the_wall
    blocked = [pair for q in straight(q_in, q_out, 0.01) for pair in planner.collisions(q)]
    assert any(other == "bin_1_base_link" for _, other in blocked), blocked
    assert planner.path_collisions(q_in, q_out)
    assert len(path) > 2
    assert np.array_equal(path[0], q_in) and np.array_equal(path[-1], q_out)
    for a, b in itertools.pairwise(path):  # finer than the planner's own 0.01 rad checks
        for q in straight(a, b, 0.004):
            assert planner.collisions(q) == [], q


def test_plan_is_deterministic(planner, over_the_wall):
    q_in, q_out, path = over_the_wall
    again = planner.plan(q_in, q_out)
    assert len(again) == len(path)
    assert all(np.array_equal(a, b) for a, b in zip(path, again))


def test_no_path_in_time_names_what_blocks_the_straight_path(planner, over_the_wall):
    q_in, q_out, _ = over_the_wall
    with pytest.raises(PlanningError, match=r"no collision-free path .* within 1e-06 s") as error:
        planner.plan(q_in, q_out, timeout=1e-6)  # OMPL stops before its first sample
    assert "bin_1_base_link" in str(error.value)


def test_free_straight_move_is_one_segment(planner):
    q_home, q_place = arms.named_pose("R2Home"), arms.named_pose("R2Place")
    path = planner.plan(q_home, q_place)
    assert len(path) == 2 and np.array_equal(path[1], q_place)


def test_unreachable_pose(planner):
    with pytest.raises(UnreachableError, match="unreachable") as error:
        planner.ik(RigidTransform(DOWN, [-6.5, -1.5, 1.0]))
    assert "mm" in str(error.value)


def test_goal_in_collision_names_the_bodies(planner, over_the_wall):
    q_in = over_the_wall[0]
    q_wall = planner.ik(RigidTransform(DOWN, [-8.0, -2.005, 0.40]), q_seed=q_in,
                        check_collisions=False)  # the tip in the bin's wall
    with pytest.raises(GoalInCollisionError, match="goal configuration .* in collision") as error:
        planner.plan(arms.named_pose("R2Place"), q_wall)
    assert "bin_1_base_link" in str(error.value)
    assert "vacuum_gripper2_cup" in str(error.value)
    with pytest.raises(GoalInCollisionError, match="every IK solution .* in collision"):
        planner.ik(RigidTransform(DOWN, [-8.0, -2.005, 0.40]), q_seed=q_in)


def test_a_start_stuck_in_collision_is_its_own_error(planner, over_the_wall):
    q_in = over_the_wall[0]
    try:
        # A 0.6 m box hanging from the cup in the bin: in its floor at every nudge of 0.3 rad.
        planner.scene.set_held_part(RigidTransform([0.0, 0.0, 0.3]), 0.6)
        assert planner.collisions(arms.named_pose("R2Home")) == []
        with pytest.raises(StartInCollisionError, match=r"start configuration .* held_part / floor"):
            planner.plan(q_in, arms.named_pose("R2Home"))
    finally:
        planner.scene.clear_held_part()


def test_obstacles_and_held_part(planner, over_the_wall):
    q_in = over_the_wall[0]
    try:
        planner.scene.set_obstacles([(RigidTransform([-8.0, -2.2, 0.35]), 0.1)])
        assert ("vacuum_gripper2_cup", "obstacle_0") in planner.collisions(q_in)
        planner.scene.set_obstacles([])
        assert planner.collisions(q_in) == []
        # A 0.3 m box hanging from the cup reaches below the bin's floor (0.12).
        planner.scene.set_held_part(RigidTransform([0.0, 0.0, 0.15]), 0.3)
        assert ("held_part", "bin_1_base_link") in planner.collisions(q_in)
        planner.scene.set_held_part(RigidTransform([0.0, 0.0, 0.05]), 0.1)
        assert planner.collisions(q_in) == []
    finally:
        planner.scene.set_obstacles([])
        planner.scene.clear_held_part()
    assert planner.collisions(q_in) == []


def test_outside_the_joint_limits(scenario):
    robots = [dataclasses.replace(r, joint_limit=2.0) if r.name == "robot2" else r
              for r in scenario.robots]
    limited = ArmPlanner(dataclasses.replace(scenario, robots=robots), "robot2")
    with pytest.raises(UnreachableError,
                       match=r"outside the joint limits: \w+_joint would be .* \[-2.000, 2.000\]"):
        limited.ik(RigidTransform(DOWN, [-8.0, -2.2, 0.45]), q_seed=arms.named_pose("R2Home"))


def test_cartesian_path_down_and_out_of_reach(planner):
    q = arms.named_pose("R2Place")
    X_WE = planner.forward_kinematics(q)
    down = RigidTransform(X_WE.rotation(), X_WE.translation() + [0.0, 0.0, -0.1])
    path, fraction = planner.cartesian_path(q, [down])
    assert fraction == 1.0
    assert len(path) == 21  # 0.1 m in 5 mm steps
    assert np.linalg.norm(planner.forward_kinematics(path[-1]).translation()
                          - down.translation()) < 2e-4
    far = RigidTransform(X_WE.rotation(), X_WE.translation() + [0.0, -1.5, 0.0])
    path, fraction = planner.cartesian_path(q, [far])
    assert 0.0 < fraction < 1.0
    assert len(path) == 1 + round(fraction * 300)


def test_time_parameterization_respects_limits(planner, over_the_wall):
    q_in, q_out, path = over_the_wall
    trajectory = planner.time_parameterize(path)
    t = np.linspace(trajectory.start_time(), trajectory.end_time(), 4001)
    v = np.abs(np.array([trajectory.EvalDerivative(ti, 1).ravel() for ti in t]))
    assert np.all(v <= planner.velocity_limits * (1 + 1e-6))
    assert np.max(v / planner.velocity_limits) > 0.5  # not needlessly slow
    assert np.allclose(trajectory.value(trajectory.start_time()).ravel(), q_in, atol=1e-9)
    assert np.allclose(trajectory.value(trajectory.end_time()).ravel(), q_out, atol=1e-6)
    assert np.allclose(trajectory.EvalDerivative(trajectory.end_time(), 1).ravel(), 0.0, atol=1e-9)
    slow = planner.time_parameterize(path, velocity_scale=0.5)
    assert slow.end_time() > trajectory.end_time()
    # It follows the planned (collision-checked) segments: still collision free.
    for ti in np.linspace(trajectory.start_time(), trajectory.end_time(), 600):
        assert planner.collisions(trajectory.value(ti).ravel()) == [], ti


def test_cartesian_trajectory_stays_on_the_line(planner):
    q = arms.named_pose("R2Place")
    X_start = planner.forward_kinematics(q)
    p0 = X_start.translation()
    p1 = p0 + [0.15, 0.0, -0.2]
    path, fraction = planner.cartesian_path(q, [RigidTransform(X_start.rotation(), p1)])
    assert fraction == 1.0
    trajectory = planner.time_parameterize(path)
    u = (p1 - p0) / np.linalg.norm(p1 - p0)
    worst = 0.0
    for t in np.linspace(trajectory.start_time(), trajectory.end_time(), 400):
        p = planner.forward_kinematics(trajectory.value(t).ravel()).translation()
        worst = max(worst, np.linalg.norm((p - p0) - ((p - p0) @ u) * u))
    assert worst < 0.002
    v = np.abs(np.array([trajectory.EvalDerivative(t, 1).ravel()
                         for t in np.linspace(0.0, trajectory.end_time(), 2001)]))
    assert np.all(v <= planner.velocity_limits * (1 + 1e-6))


TOPPRA_WITHOUT_PYPLOT = """
import sys
import numpy as np
from omtp_drake.control.motion.timing import time_parameterize
trajectory = time_parameterize([np.zeros(6), np.full(6, 0.5)], np.full(6, 3.0), np.full(6, 4.0))
assert trajectory.end_time() > 0.1
assert "toppra" in sys.modules and "matplotlib.pyplot" not in sys.modules, "pyplot imported"
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import toppra.algorithm.algorithm as algorithm
assert type(plt).__name__ == "module" and plt.figure is algorithm.plt.figure
print("ok")
"""


def test_timing_imports_toppra_without_pyplot_and_pyplot_stays_real():
    """TOPP-RA's first use does not import matplotlib's pyplot (toppra's algorithm module
    imports it for a plotting method); pyplot imported afterwards is the real module, and
    toppra's own plots reach it. (A fresh process: this one may hold pyplot already.)"""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", TOPPRA_WITHOUT_PYPLOT], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr
