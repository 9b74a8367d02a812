"""Tool paths and the pick policy (control.tool_paths, control.pick_policy): paths, timing, slots, grasps."""

import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.cell import arms
from omtp_drake.control.pick_policy import BLEND_DROP, WRIST_PER_YAW, WRIST_WIND_LIMIT, PickPlanner
from omtp_drake.control.tool_paths import (
    MAX_TOOL_ACCELERATION,
    MAX_TOOL_ROTATION_ACCELERATION,
    MAX_TOOL_ROTATION_SPEED,
    MIN_DURATION,
    Path,
    Segment,
    SegmentKind,
    hold,
    progress,
    rotations_about,
    timing,
    tool_down,
    wrap,
    yaw_of,
)
from omtp_drake.scenario import BinGeometry, load_scenario

BIN = BinGeometry.from_model()
X_WR = RigidTransform(RollPitchYaw(0, 0, 1.57), [-7.8, -1.5, 0.7])  # robot 2's base
X_WBIN = RigidTransform([-8.0, -2.2, 0.0])


@pytest.mark.parametrize("ramp", [0.1, 0.25, 0.5])
def test_progress_is_smooth_and_ends_at_rest(ramp):
    tau = np.linspace(0, 1, 2001)
    s = np.array([progress(x, ramp) for x in tau])
    v = np.gradient(s, tau)
    assert s[0] == 0 and s[-1] == pytest.approx(1) and abs(v[0]) < 1e-3 and abs(v[-1]) < 1e-3
    assert np.all(np.diff(s) >= 0)
    assert np.abs(np.diff(v)).max() < 0.01  # no velocity steps
    # Peak over mean speed is the documented 1 / (1 - ramp).
    assert v.max() == pytest.approx(1 / (1 - ramp), rel=1e-3)


def test_arc_is_level_about_the_centre_and_ends_where_asked():
    X0, X1 = tool_down(np.array([1.0, 0.0, 0.5]), 0.0), tool_down(np.array([0.0, 1.0, 0.5]), 1.0)
    arc = Segment(SegmentKind.ARC, 0.0, 2.0, X0, X1, (0.0, 0.0))
    assert arc.pose(2.0).IsNearlyEqualTo(X1, 1e-9)
    assert arc.pose(-1.0).IsNearlyEqualTo(X0, 1e-9)
    for t in np.linspace(0, 2, 9):
        p = arc.pose(t).translation()
        assert np.hypot(p[0], p[1]) == pytest.approx(1.0) and p[2] == pytest.approx(0.5)
        assert arc.pose(t).rotation().col(2) == pytest.approx([0, 0, -1])


def turn_angles(R: np.ndarray) -> np.ndarray:
    """The angle (rad) of each turn R[k] -> R[k + 1] of the rotations R (N, 3, 3): for a turn
    by angle q, |R[k + 1] - R[k]|_F = 2 sqrt(2) sin(q / 2), accurate for small turns too."""
    chord = np.linalg.norm(np.diff(R, axis=0), axis=(1, 2)) / (2 * math.sqrt(2))
    return 2 * np.arcsin(np.clip(chord, 0.0, 1.0))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-2, 2), min_size=3, max_size=3), st.lists(st.floats(-2, 2), min_size=3,
       max_size=3), st.floats(-3, 3), st.floats(-3, 3), st.floats(0.1, 1.0))
def test_a_move_never_exceeds_its_speed_or_acceleration_and_is_no_slower_than_they_require(
        p0, p1, yaw0, yaw1, speed):
    """Sampled finely, a planned line's tool speed peaks at most ``speed``, its
    acceleration at most MAX_TOOL_ACCELERATION, its turn rate at most
    MAX_TOOL_ROTATION_SPEED; and one of the limits (or MIN_DURATION) binds."""
    planner = PickPlanner(RigidTransform(), speed)
    X0, X1 = tool_down(np.array(p0), yaw0), tool_down(np.array(p1), yaw1)
    segment = planner.move(SegmentKind.LINE, 0.0, X0, X1)
    ts = np.linspace(0, segment.duration, 2001)
    p, R = Path((segment,)).poses(ts)  # segment.pose at each time (test_poses_at_many_times_...)
    dt = ts[1] - ts[0]
    v = np.linalg.norm(np.diff(p, axis=0), axis=1) / dt
    a = np.linalg.norm(np.diff(p, 2, axis=0), axis=1) / dt**2
    w = turn_angles(R) / dt
    assert v.max() <= speed * 1.01 + 1e-9
    assert a.max() <= MAX_TOOL_ACCELERATION * 1.02 + 1e-9
    assert w.max() <= MAX_TOOL_ROTATION_SPEED * 1.01
    assert segment.pose(segment.t1).IsNearlyEqualTo(X1, 1e-9)
    alpha = np.abs(np.diff(w)) / dt  # the slerp turns about one axis
    assert alpha.max() <= MAX_TOOL_ROTATION_ACCELERATION * 1.02 + 1e-9
    binds = [v.max() >= 0.98 * speed, a.max() >= 0.97 * MAX_TOOL_ACCELERATION,
             w.max() >= 0.98 * MAX_TOOL_ROTATION_SPEED, alpha.max() >= 0.97 * MAX_TOOL_ROTATION_ACCELERATION,
             segment.duration == MIN_DURATION]
    assert any(binds), (segment.duration, v.max(), a.max(), w.max(), alpha.max())


@settings(max_examples=30)
@given(st.tuples(*[st.floats(-3.0, 3.0)] * 3), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_a_straight_path_turns_at_a_steady_rate_about_one_axis(rpy, s1, s2):
    """The slerp of a LINE: a rotation at each fraction, its end the goal's, and turning by
    s1 then s2 is turning by s1 + s2 (one fixed axis, the angle proportional to s)."""
    X0, X1 = tool_down(np.zeros(3), 0.3), RigidTransform(RollPitchYaw(*rpy), [0.1, 0.2, 0.3])
    line = Segment(SegmentKind.LINE, 0.0, 1.0, X0, X1)
    assert line.pose(1.0).IsNearlyEqualTo(X1, 1e-9)
    R_SG = (X0.rotation().inverse() @ X1.rotation()).ToAngleAxis()
    rotvec = R_SG.angle() * R_SG.axis()
    R1, R2, R12 = rotations_about(rotvec, np.array([s1, s2, s1 + s2]))
    assert np.allclose(R1 @ R1.T, np.eye(3), atol=1e-12) and np.linalg.det(R1) == pytest.approx(1.0)
    assert np.allclose(R1 @ R2, R12, atol=1e-12)
    R_goal = X0.rotation().matrix().T @ X1.rotation().matrix()
    assert np.allclose(rotations_about(rotvec, np.array([1.0]))[0], R_goal)


def test_a_pick_path_imports_no_scipy():
    """A task's tool paths (slerps, blends) need no scipy: its import would cost each run's
    process ~0.6 CPU s of start-up."""
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from omtp_drake.control.pick_policy import _overlap\n"
        "from omtp_drake.control.tool_paths import Segment, SegmentKind, tool_down\n"
        "X0, X1 = tool_down(np.zeros(3), 0.0), tool_down(np.array([0.0, 0.0, 0.3]), 1.0)\n"
        "up = Segment(SegmentKind.LINE, 0.0, 1.0, X0, X1)\n"
        "over = Segment(SegmentKind.ARC, 1.0, 2.0, X1, tool_down(np.array([0.5, 0.5, 0.3]), 2.0))\n"
        "up.motions(np.linspace(0.0, 1.0, 5))\n"
        "print(round(_overlap(up, over, 0.01, 0.01), 9), 'scipy' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    overlap, scipy_loaded = out.stdout.split()
    assert 0.0 < float(overlap) < 0.25 and scipy_loaded == "False"


def test_path_pose_and_done():
    X0, X1 = tool_down(np.zeros(3), 0.0), tool_down(np.array([0.0, 0.0, 1.0]), 0.0)
    a = Segment(SegmentKind.LINE, 1.0, 1.0, X0, X1)
    b = Segment(SegmentKind.LINE, 2.0, 1.0, X1, X0)
    path = Path((a, b))
    assert path.pose_at(1.5).translation()[2] == pytest.approx(0.5)
    assert path.pose_at(10.0).IsNearlyEqualTo(X0, 1e-12)
    assert not path.done(2.9) and path.done(3.0) and path.end_time == 3.0
    assert Path().pose_at(0.0) is None and Path().done(0.0)


def test_poses_at_many_times_are_pose_at_each_of_them():
    planner = PickPlanner(X_WR, 1.0)
    X0 = tool_down(np.array([-7.3, -1.2, 1.0]), 0.3)
    X1 = tool_down(np.array([-8.0, -2.2, 0.9]), -1.0)
    X2 = tool_down(np.array([-8.0, -2.2, 0.7]), -1.2)
    paths = [
        planner.travel(0.3, X0, X1),  # blended: line, arc, line
        hold(0.2, X1),
        Path((planner.move(SegmentKind.LINE, 0.1, X1, X2), planner.move(SegmentKind.LINE, 0.9, X2, X1, 0.2))),
        Path((planner.move(SegmentKind.ARC, 0.1, X0, X1),)),
    ]
    for path in paths:
        t = np.arange(0.0, path.end_time + 0.3, 0.01)
        p, R = path.poses(t)
        for k in range(len(t)):
            X = path.pose_at(t[k])
            assert np.allclose(p[k], X.translation(), atol=1e-12, rtol=0)
            assert np.allclose(R[k], X.rotation().matrix(), atol=1e-12, rtol=0)


def test_pose_table_gives_the_path_in_the_arm_base_at_its_samples():
    """The controller's table (what its updates read) is X_BW @ pose_at(t) at
    each sample time from the first at or after the fill, the end pose after the
    path's end, and nothing between samples."""
    from omtp_drake.control.pick_and_place.system import PoseTable

    planner = PickPlanner(X_WR, 1.0)
    path = planner.travel(0.3, tool_down(np.array([-7.3, -1.2, 1.0]), 0.3),
                          tool_down(np.array([-8.0, -2.2, 0.9]), -1.0))
    X_BW = X_WR.inverse()
    table = PoseTable()
    table.fill(path, 0.304, 0.01, X_BW)
    assert table.path is path
    assert table.pose(0.30) is None  # before the fill's first sample
    assert table.pose(0.315) is None  # between samples
    for t in np.arange(31, round(path.end_time / 0.01) + 40) * 0.01:
        X_BE, X_expected = table.pose(t), X_BW @ path.pose_at(min(t, path.end_time))
        assert X_BE.IsNearlyEqualTo(X_expected, 1e-12), t
    empty = PoseTable()
    empty.fill(Path(), 0.0, 0.01, X_BW)
    assert empty.pose(0.0) is None


@pytest.mark.parametrize("size, per_layer", [(0.05, 36), (0.1, 9), (0.2, 1)])
def test_slots_fill_the_bin_in_layers_inside_its_walls(size, per_layer):
    planner = PickPlanner(X_WR, 1.0)
    slots = np.array([planner.slot(X_WBIN, BIN, size, k) for k in range(per_layer + 1)])
    first_layer = slots[:per_layer]
    # Each part fits inside the inner walls, and parts do not overlap.
    p_B = first_layer - X_WBIN.translation()
    assert np.all(np.abs(p_B[:, :2]) + size / 2 <= BIN.inner_half_width + 1e-9)
    if per_layer > 1:
        gaps = [np.max(np.abs(a[:2] - b[:2])) for i, a in enumerate(first_layer)
                for b in first_layer[i + 1:]]
        assert min(gaps) >= size
    # The next part starts a new layer, one part higher (or at the rim's release height).
    assert slots[per_layer][2] >= slots[0][2] - 1e-9
    assert np.allclose(slots[per_layer][:2], slots[0][:2])
    # Never released with the cup below the rim.
    assert np.all(slots[:, 2] >= BIN.height + 0.02 - 1e-9)


def test_slot_follows_a_moved_and_turned_bin():
    planner = PickPlanner(X_WR, 1.0)
    X_moved = RigidTransform(RollPitchYaw(0, 0, 0.5), [-8.3, -2.4, 0.0])
    for k in range(9):
        p = planner.slot(X_moved, BIN, 0.1, k)
        p_B = X_moved.inverse() @ p
        assert np.all(np.abs(p_B[:2]) + 0.05 <= BIN.inner_half_width + 1e-9)


@settings(max_examples=80, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi), st.floats(0.05, 0.2))
def test_grasp_pose_is_tool_down_above_the_top_face_and_square_with_the_part(part_yaw, tool_yaw,
                                                                           size):
    planner = PickPlanner(X_WR, 1.0)
    X_WP = RigidTransform(RollPitchYaw(0, 0, part_yaw), [-8.3, -1.23, size / 2])
    X_now = tool_down(np.array([-8.3, -1.23, 0.6]), tool_yaw)
    X = planner.grasp_pose(X_WP, size, X_now, 0.1)
    assert X.translation() == pytest.approx([-8.3, -1.23, size + 0.1])
    assert X.rotation().col(2) == pytest.approx([0, 0, -1], abs=1e-9)
    # The tool's yaw equals the part's modulo 90 deg, and is the turn nearest the tool's.
    offset = wrap(yaw_of(X) - part_yaw)
    assert min(abs(offset - k * math.pi / 2) for k in range(-2, 3)) < 1e-9
    assert abs(wrap(yaw_of(X) - tool_yaw)) <= math.pi / 4 + 1e-9


@settings(max_examples=300, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-10.0, 10.0), st.floats(-2 * math.pi, 2 * math.pi))
def test_square_yaw_keeps_the_wrist_within_its_wind_limit(yaw, carried, wrist):
    """The chosen yaw is square with ``yaw``, turns less than 180 deg, and leaves the
    last wrist joint within the wind limit, or (already wound past it) unwinds it by
    at least 90 deg; with the wrist near home it is the nearest turn."""
    chosen = PickPlanner.square_yaw(yaw, carried, wrist)
    turn = chosen - carried
    assert min(abs(wrap(chosen - yaw) - k * math.pi / 2) for k in range(-2, 3)) < 1e-9
    assert abs(turn) < math.pi
    after = wrist + WRIST_PER_YAW * turn
    assert abs(after) <= max(WRIST_WIND_LIMIT, abs(wrist) - math.pi / 2) + 1e-9
    if abs(wrist) <= WRIST_WIND_LIMIT - math.pi / 4:
        assert abs(turn) <= math.pi / 4 + 1e-9
        assert chosen == pytest.approx(PickPlanner.square_yaw(yaw, carried))


def test_a_run_of_same_way_turns_does_not_wind_the_wrist_past_its_limit():
    """Twenty picks that each want a +60 deg turn (nearest-turn alone: +20 rad of
    wrist): the wrist stays within the limit, turning back a quarter now and then."""
    wrist, carried = 0.0, 0.0
    for _ in range(20):
        chosen = PickPlanner.square_yaw(carried + math.radians(60), carried, wrist)
        wrist += WRIST_PER_YAW * (chosen - carried)
        carried = chosen
        assert abs(wrist) <= WRIST_WIND_LIMIT + 1e-9


@pytest.mark.parametrize("robot", ["robot1", "robot2"])
def test_wrist_per_yaw_is_the_arms_kinematics(robot):
    """Tool down at Home, turning the last wrist joint by 0.3 rad turns the tool's
    world yaw by 0.3 / WRIST_PER_YAW."""
    config = {r.name: r for r in load_scenario("omtp_factory").robots}[robot]
    plant = arms.make_control_plant(config, [0.0, 0.0, -9.81])
    context = plant.CreateDefaultContext()
    tip = plant.GetFrameByName(f"{config.gripper}_tip")
    q = np.array(arms.named_pose("Home", config))
    plant.SetPositions(context, q)
    X0 = tip.CalcPoseInWorld(context)
    plant.SetPositions(context, q + [0, 0, 0, 0, 0, 0.3])
    X1 = tip.CalcPoseInWorld(context)
    assert X0.rotation().col(2) == pytest.approx([0, 0, -1], abs=1e-5)
    assert wrap(yaw_of(X1) - yaw_of(X0)) == pytest.approx(0.3 / WRIST_PER_YAW, abs=1e-6)


def test_travel_rises_over_the_bin_and_never_dips_below_its_ends():
    planner = PickPlanner(X_WR, 1.0, transfer_clearance=0.05)
    X_now = tool_down(np.array([-8.3, -1.23, 0.35]), 0.0)
    p_slot = planner.slot(X_WBIN, BIN, 0.2, 0)
    X_goal = tool_down(p_slot, 0.0)
    clear = planner.clearance_height(X_WBIN, BIN, 0.2, [X_now.translation(), p_slot])
    assert clear == pytest.approx(BIN.height + 0.2 + 0.05)
    path = planner.travel(0.0, X_now, X_goal, clear)
    kinds = [s.kind for s in path.segments]
    assert kinds == [SegmentKind.LINE, SegmentKind.ARC, SegmentKind.LINE]
    times = np.linspace(0, path.end_time, 600)
    points = np.array([path.pose_at(t).translation() for t in times])
    assert points[:, 2].min() >= min(0.35, p_slot[2]) - 1e-9
    assert points[:, 2].max() == pytest.approx(clear + BLEND_DROP)
    # Over the bin (and 0.1 m around it), a held 0.2 m part clears the rim.
    near = np.all(np.abs(points[:, :2] - X_WBIN.translation()[:2]) < BIN.inner_half_width + 0.3, axis=1)
    moving = np.r_[True, np.linalg.norm(np.diff(points[:, :2], axis=0), axis=1) > 1e-6]
    assert np.all(points[near & moving & (times < path.segments[2].t0), 2] >= clear - 1e-9)
    assert path.pose_at(path.end_time).IsNearlyEqualTo(X_goal, 1e-9)
    # Blended: the arc starts before the rise ends, the descent before the arc ends,
    # so the tool does not stop at the corners.
    up, arc, down = path.segments
    assert arc.t0 < up.t1 and down.t0 < arc.t1
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(times)
    corners = (times[1:] > up.t0 + 0.2) & (times[1:] < down.t1 - 0.2)
    assert speed[corners].min() > 0.05
    assert path.end_time < (up.t1 - up.t0) + (arc.t1 - arc.t0) + (down.t1 - down.t0) - 0.15
    # Far from the bin, no clearance is needed.
    far = [np.array([-7.0, -1.0, 0.3]), np.array([-7.2, -0.9, 0.4])]
    assert planner.clearance_height(X_WBIN, BIN, 0.2, far) == -math.inf


def test_a_long_arc_cruises_at_the_speed_limit_after_an_acceleration_limited_ramp():
    X0 = tool_down(np.array([1.0, 0.0, 0.5]), 0.0)
    X1 = tool_down(np.array([0.0, 1.0, 0.5]), math.pi / 2)
    T, ramp = timing(SegmentKind.ARC, X0, X1, 0.8, (0.0, 0.0))
    # pi/2 m at 0.8 m/s, plus one sin^2 ramp peaking at MAX_TOOL_ACCELERATION.
    ramp_time = math.pi * 0.8 / (2 * MAX_TOOL_ACCELERATION)
    assert T == pytest.approx((math.pi / 2) / 0.8 + ramp_time)
    assert ramp * T == pytest.approx(ramp_time)



@settings(max_examples=30, deadline=None)
@given(st.floats(0.3, 1.0), st.floats(-3.0, 3.0), st.floats(0.0, 1.2), st.floats(0.0, 1.2),
       st.floats(0.0, 1.0), st.sampled_from([None, 0.0, 0.1]), st.sampled_from([None, 0.0, 0.1]))
# Legs shorter than 1 um (a turn of 1.2e-7 rad, a drop of 6e-8 m) once ended the
# path that far from the goal: drawn by users' runs, kept as regressions.
@example(radius=1.0, turn=1.192092896e-07, z0=0.0, z1=0.0, min_height=1.0, clear_start=None, clear_end=None)
@example(radius=1.0, turn=1.0, z0=5.960464477539063e-08, z1=0.0, min_height=0.0, clear_start=None,
         clear_end=None)
@example(radius=1.0, turn=0.0, z0=0.5, z1=0.5 - 1e-7, min_height=0.0, clear_start=0.0, clear_end=0.0)
def test_a_blended_travel_keeps_its_speed_limit_and_its_clearances(
    radius, turn, z0, z1, min_height, clear_start, clear_end
):
    """Up, arc, down blended: never faster than the limit, never lower than its ends,
    no sideways motion before the tool is ``clear_start`` above its start (default:
    within BLEND_DROP of the travel height) nor after it is ``clear_end`` above the goal."""
    planner = PickPlanner(RigidTransform(), 1.0)
    X_now = tool_down(np.array([radius, 0.0, z0]), 0.0)
    X_goal = tool_down(np.array([radius * math.cos(turn), radius * math.sin(turn), z1]), turn)
    path = planner.travel(0.0, X_now, X_goal, min_height, clear_start=clear_start, clear_end=clear_end)
    times = np.linspace(0, max(path.end_time, 0.1), 1500)  # (a hold when already there)
    p = path.poses(times)[0]  # path.pose_at at each time (test_poses_at_many_times_...)
    speed = np.linalg.norm(np.diff(p, axis=0), axis=1) / np.diff(times)
    assert speed.max() <= 1.01
    assert p[:, 2].min() >= min(z0, z1) - 1e-9
    z_top = p[:, 2].max()
    sideways = np.r_[np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1) > 1e-7, False]
    if sideways.any():
        first, last = np.argmax(sideways), len(sideways) - 1 - np.argmax(sideways[::-1])
        # (A travel that does not rise that much rises all the way first.)
        start_clear = z_top - BLEND_DROP - z0 if clear_start is None else min(clear_start, z_top - z0)
        end_clear = z_top - BLEND_DROP - z1 if clear_end is None else min(clear_end, z_top - z1)
        assert p[first, 2] - z0 >= start_clear - 2e-3
        assert p[last + 1, 2] - z1 >= end_clear - 2e-3
    assert path.pose_at(path.end_time).IsNearlyEqualTo(X_goal, 1e-9)
