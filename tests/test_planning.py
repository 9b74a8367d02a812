"""The pick-and-place planner's maths (omtp_drake.planning): paths, timing, slots, grasps."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydrake.math import RigidTransform, RollPitchYaw

from omtp_drake.planning import (MAX_TOOL_ROTATION_SPEED, SPEED_MARGIN, Path, PickPlanner, Segment,
                                 SegmentKind, duration, progress, tool_down, wrap, yaw_of)
from omtp_drake.scenario import BinGeometry

BIN = BinGeometry.from_model()
X_WR = RigidTransform(RollPitchYaw(0, 0, 1.57), [-7.8, -1.5, 0.7])  # robot 2's base
X_WBIN = RigidTransform([-8.0, -2.2, 0.0])


def test_progress_is_smooth_and_ends_at_rest():
    tau = np.linspace(0, 1, 2001)
    s = np.array([progress(x) for x in tau])
    v = np.gradient(s, tau)
    assert s[0] == 0 and s[-1] == pytest.approx(1) and abs(v[0]) < 1e-3 and abs(v[-1]) < 1e-3
    assert np.all(np.diff(s) >= 0)
    assert np.abs(np.diff(v)).max() < 0.01  # no velocity steps
    # Peak over mean speed is the documented 4/3.
    assert v.max() == pytest.approx(1 / (1 - 0.25), rel=1e-3)


def test_arc_is_level_about_the_centre_and_ends_where_asked():
    X0, X1 = tool_down(np.array([1.0, 0.0, 0.5]), 0.0), tool_down(np.array([0.0, 1.0, 0.5]), 1.0)
    arc = Segment(SegmentKind.ARC, 0.0, 2.0, X0, X1, (0.0, 0.0))
    assert arc.pose(2.0).IsNearlyEqualTo(X1, 1e-9)
    assert arc.pose(-1.0).IsNearlyEqualTo(X0, 1e-9)
    for t in np.linspace(0, 2, 9):
        p = arc.pose(t).translation()
        assert np.hypot(p[0], p[1]) == pytest.approx(1.0) and p[2] == pytest.approx(0.5)
        assert arc.pose(t).rotation().col(2) == pytest.approx([0, 0, -1])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-2, 2), min_size=3, max_size=3), st.lists(st.floats(-2, 2), min_size=3,
       max_size=3), st.floats(-3, 3), st.floats(-3, 3), st.floats(0.1, 1.0))
def test_a_move_never_exceeds_its_speed(p0, p1, yaw0, yaw1, speed):
    """Sampled finely, a planned line's tool speed peaks at most SPEED_MARGIN x speed,
    and its turn rate at most MAX_TOOL_ROTATION_SPEED."""
    planner = PickPlanner(RigidTransform(), speed)
    X0, X1 = tool_down(np.array(p0), yaw0), tool_down(np.array(p1), yaw1)
    segment = planner.move(SegmentKind.LINE, 0.0, X0, X1)
    ts = np.linspace(0, segment.duration, 400)
    poses = [segment.pose(t) for t in ts]
    dt = ts[1] - ts[0]
    v = max(np.linalg.norm(b.translation() - a.translation()) / dt for a, b in zip(poses, poses[1:]))
    w = max((a.rotation().inverse() @ b.rotation()).ToAngleAxis().angle() / dt
            for a, b in zip(poses, poses[1:]))
    assert v <= SPEED_MARGIN * speed * 1.01 + 1e-9
    assert w <= MAX_TOOL_ROTATION_SPEED * 1.01
    assert segment.pose(segment.t1).IsNearlyEqualTo(X1, 1e-9)


def test_path_pose_and_done():
    X0, X1 = tool_down(np.zeros(3), 0.0), tool_down(np.array([0.0, 0.0, 1.0]), 0.0)
    a = Segment(SegmentKind.LINE, 1.0, 1.0, X0, X1)
    b = Segment(SegmentKind.LINE, 2.0, 1.0, X1, X0)
    path = Path((a, b))
    assert path.pose_at(1.5).translation()[2] == pytest.approx(0.5)
    assert path.pose_at(10.0).IsNearlyEqualTo(X0, 1e-12)
    assert not path.done(2.9) and path.done(3.0) and path.end_time == 3.0
    assert Path().pose_at(0.0) is None and Path().done(0.0)


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
    heights = [path.pose_at(t).translation()[2] for t in np.linspace(0, path.end_time, 300)]
    assert min(heights) >= min(0.35, p_slot[2]) - 1e-9
    assert max(heights) == pytest.approx(clear)
    assert path.pose_at(path.end_time).IsNearlyEqualTo(X_goal, 1e-9)
    # Far from the bin, no clearance is needed.
    far = [np.array([-7.0, -1.0, 0.3]), np.array([-7.2, -0.9, 0.4])]
    assert planner.clearance_height(X_WBIN, BIN, 0.2, far) == -math.inf


def test_duration_of_an_arc_covers_its_length_at_the_margin_speed():
    X0 = tool_down(np.array([1.0, 0.0, 0.5]), 0.0)
    X1 = tool_down(np.array([0.0, 1.0, 0.5]), math.pi / 2)
    d = duration(SegmentKind.ARC, X0, X1, 0.8, (0.0, 0.0))
    assert d == pytest.approx((4 / 3) * (math.pi / 2) / 0.8)
