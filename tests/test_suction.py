"""The vacuum gripper (omtp_drake.cell.suction), both backends, on the suction rig
(tests/suction_rig.py: a 5-DOF tool over a floor with parts)."""

import math

import numpy as np
import pytest
from pydrake.common.yaml import yaml_load_typed
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.systems.framework import DiagramBuilder
from suction_rig import (
    CUP_OFFSET,
    GRIPPER,
    PART_Z,
    PRESS,
    SIZE,
    TOP,
    H,
    Rig,
    build_rig,
    hold,
    logged_at,
    pick_motion,
    plant_config,
    pose_change,
    tool_q,
    trajectory,
)

from omtp_drake.assets import MODELS_DIR, expand_xacro
from omtp_drake.cell.suction import GripperState
from omtp_drake.cell.suction_constraints import declare_suction_constraints, octahedron
from omtp_drake.cell.suction_holds import (
    ForceSuctionGripper,
    add_suction_gripper,
    connect_spatial_forces,
    sync_weld,
)
from omtp_drake.errors import ConfigError, StateError, UnknownNameError
from omtp_drake.scenario import SuctionConfig

BACKENDS = ("weld", "force")

# ----------------------------------------------------------------------------
# Configuration


def test_config_defaults_are_valid_and_load_from_yaml():
    SuctionConfig().validate()
    config = yaml_load_typed(schema=SuctionConfig, data="backend: force\ncheck_rate_hz: 30.0\n"
                             "consecutive_checks: 3\napply_reaction: false\n")
    config.validate()
    assert (config.backend, config.check_rate_hz, config.consecutive_checks,
            config.apply_reaction) == ("force", 30.0, 3, False)


@pytest.mark.parametrize("field_name, value, words", [
    ("backend", "glue", ["backend", "glue", "weld", "force"]),
    ("check_rate_hz", 5.0, ["check_rate_hz", "5.0", "[10, 1000] Hz"]),
    ("check_rate_hz", math.nan, ["check_rate_hz", "nan"]),
    ("max_angle_deg", 95.0, ["max_angle_deg", "95.0", "(0, 90)"]),
    ("consecutive_checks", 0, ["consecutive_checks", "0", ">= 1"]),
    ("stiffness", -1.0, ["stiffness", "-1.0", "(0, inf)"]),
    ("damping", -2.0, ["damping", "-2.0", "[0, inf)"]),
    ("angular_stiffness", math.inf, ["angular_stiffness", "inf"]),
    ("max_hold_distance", 0.0, ["max_hold_distance", "0.0", "(0, inf)"]),
])
def test_config_validation_names_field_value_and_range(field_name, value, words):
    config = SuctionConfig(**{field_name: value})
    with pytest.raises(ConfigError) as info:
        config.validate()
    for word in words:
        assert word in str(info.value)


def test_add_suction_gripper_validates_config():
    with pytest.raises(ConfigError, match="backend"):
        build_rig("weld", hold(tool_q(0, 0, 0.5)), config=SuctionConfig(backend="magnet"))


# ----------------------------------------------------------------------------
# Weld constraints' geometry


def test_octahedron_of_six_distances_is_rigid():
    """The six lengths fix all 6 DOF of the relative pose (full-rank rigidity matrix)."""
    a, b, pairs = octahedron()
    assert len({(i, j) for i, j in pairs}) == 6
    # d(distance_ij) = u . (w x b_j + v) = (b_j x u) . w + u . v for a twist [w, v] of the
    # part side, u = unit(b_j - a_i); rotations scaled by the triangle radius R.
    R = np.linalg.norm(a[0])
    rows = []
    for i, j in pairs:
        u = (b[j] - a[i]) / np.linalg.norm(b[j] - a[i])
        rows.append(np.concatenate([np.cross(b[j], u) / R, u]))
    s = np.linalg.svd(np.array(rows), compute_uv=False)
    assert s[-1] > 0.25 * s[0]  # well conditioned, not just full rank
    # Not collinear: each triangle spans a plane.
    assert np.linalg.matrix_rank(a[1:] - a[0]) == 2 and np.linalg.matrix_rank(b[1:] - b[0]) == 2


# ----------------------------------------------------------------------------
# State output and the two-checks rule


@pytest.mark.parametrize("backend", BACKENDS)
def test_state_fields_and_two_consecutive_checks(backend):
    rig = build_rig(backend, hold(tool_q(0.04, 0, TOP - PRESS)), parts=[(0, 0, 0)])
    state = rig.state()
    assert isinstance(state, GripperState)
    assert (state.enabled, state.attached, state.part, state.X_CP) == (False, False, "", None)
    rig.command(True)
    rig.simulator.AdvanceTo(0.05)  # one check (t = 0, at once): touching, not yet attached
    state = rig.state()
    assert state.enabled and not state.attached and state.part == "" and math.isnan(state.since)
    assert rig.cup_part_contacts() > 0
    rig.simulator.AdvanceTo(0.12)  # second check (t = 0.1)
    if backend == "force":  # held from the check on
        assert rig.state().attached and rig.state().since == pytest.approx(0.1)
    else:  # decided; held (and reported) once the runtime syncs the constraints
        assert not rig.state().attached
        assert rig.held_body() is None
        sync_weld(rig.gripper, rig.plant, rig.context)
        assert rig.state().attached and rig.state().since == pytest.approx(0.12)
    state = rig.state()
    assert state.enabled and state.attached and state.part == "part_0"
    assert state.last_release == ""
    # X_CP: the cup looks down, so the part centre is ~0.1 m along +Cz, 4 cm to the side.
    p_CP = state.X_CP.translation()
    assert p_CP[2] == pytest.approx(SIZE / 2 - PRESS, abs=1e-3)
    assert math.hypot(p_CP[0], p_CP[1]) == pytest.approx(0.04, abs=1e-3)
    if backend == "weld":
        assert rig.held_body() == int(rig.parts[0].index())


def _checks(rig: Rig, t_end: float) -> tuple[list[float], float]:
    """Steps the rig to ``t_end`` one plant step at a time (a weld synced after each, as
    the driver does); returns the times of the contact checks that ran (each with a
    touch) and when the part was held (nan: not)."""
    checks: list[float] = []
    while rig.time < t_end - 1e-9:
        rig.simulator.AdvanceTo(round((math.floor(rig.time / rig.time_step + 1e-9) + 1) * rig.time_step, 9))
        if rig.gripper.config.backend == "weld":
            sync_weld(rig.gripper, rig.plant, rig.context)
        memory = rig.gripper._get_memory(rig.gripper.GetMyContextFromRoot(rig.context))
        if memory.last_check > -math.inf and (not checks or memory.last_check > checks[-1] + 1e-9):
            checks.append(memory.last_check)
    return checks, rig.state().since


@pytest.mark.parametrize("backend", BACKENDS)
def test_first_check_at_once_after_enabling_then_every_tenth_of_a_second(backend):
    """The course plugin's rule: enabled at 0.333 s with the cup pressed on the part, it
    checks at the first step after (0.34 s), attaches on its second check 0.1 s later
    (0.44 s; the weld is made at the next step's sync) and not before."""
    rig = build_rig(backend, hold(tool_q(0.0, 0, TOP - PRESS)), log=False)
    rig.advance_to(0.333)  # pressed on the part, suction off: no check runs
    assert not rig.state().enabled and rig.cup_part_contacts() > 0
    rig.command(True)
    checks, _ = _checks(rig, 0.43)
    assert checks == pytest.approx([0.34]) and not rig.state().attached
    checks, since = _checks(rig, 0.6)
    assert checks == pytest.approx([0.34, 0.44, 0.54])  # and on, while it holds
    assert since == pytest.approx(0.44 if backend == "force" else 0.45)


def test_enabled_again_soon_after_a_check_waits_for_the_rate():
    """Off and on again 0.03 s after a check: the next check is 0.1 s after the last one
    (the plugin's update rate counts from its last check, enabled or not since)."""
    rig = build_rig("force", hold(tool_q(0.0, 0, TOP - PRESS)), log=False)
    rig.advance_to(0.2)
    rig.command(True)
    rig.simulator.AdvanceTo(0.205)  # the check at 0.2: one touch
    rig.command(False)
    rig.simulator.AdvanceTo(0.225)
    rig.command(True)
    checks, since = _checks(rig, 0.45)
    assert checks == pytest.approx([0.2, 0.3, 0.4])  # not 0.23: 0.1 s after the last check
    assert since == pytest.approx(0.4)  # the count started again at the disable


@pytest.mark.parametrize("backend", BACKENDS)
def test_interrupted_touch_restarts_the_count(backend):
    """Touching at checks 0 and 2 but not 1 does not attach; a 2nd touch in a row does."""
    down, up = tool_q(0, 0, TOP - PRESS), tool_q(0, 0, TOP + 0.005)
    motion = trajectory([(0.0, down), (0.02, down), (0.03, up), (0.17, up), (0.18, down),
                         (1.0, down)], accel=1e6)
    rig = build_rig(backend, motion)
    rig.command(True)
    rig.advance_to(0.22)  # checks at 0 (touch), 0.1 (apart), 0.2 (touch)
    assert not rig.state().attached
    rig.advance_to(0.4)  # check at 0.3 (touch): second in a row
    assert rig.state().attached
    if backend == "force":
        assert rig.state().since == pytest.approx(0.3)
    else:  # at the chunk's sync: 0.35, or 0.3 when the chunk ends a rounding error after the check
        assert 0.3 - 1e-9 <= rig.state().since <= 0.35 + 1e-9


def test_weld_attach_is_dropped_if_the_part_is_gone_at_the_sync():
    """Decided at a check, but the tool lifted before the runtime's sync: no attach."""
    down, up = tool_q(0, 0, TOP - PRESS), tool_q(0, 0, TOP + 0.005)
    motion = trajectory([(0.0, down), (0.11, down), (0.12, up), (1.0, up)], accel=1e6)
    rig = build_rig("weld", motion, log=False)
    rig.command(True)
    rig.simulator.AdvanceTo(0.105)  # checks at 0 and 0.1: decided
    assert not rig.state().attached and rig.gripper.pending_part(
        rig.gripper.GetMyContextFromRoot(rig.context)) == "part_0"
    rig.simulator.AdvanceTo(0.14)  # lifted; the check at 0.2 not yet run
    assert rig.cup_part_contacts() == 0
    sync_weld(rig.gripper, rig.plant, rig.context)
    assert not rig.state().attached
    assert rig.held_body() is None
    rig.advance_to(0.4)
    assert not rig.state().attached and rig.X_WP().translation()[2] < PART_Z + 1e-3


def test_unknown_part_name_is_reported():
    rig = build_rig("force", hold(tool_q(0, 0, 0.5)), log=False)
    with pytest.raises(UnknownNameError, match="part_0"):
        rig.gripper.part_body_index("part_9")
    assert rig.gripper.part_names() == ["part_0"]


def test_rig_steps_at_a_given_time_step_and_refuses_one_out_of_range():
    assert H == 0.01  # the station's default
    rig = build_rig("weld", hold(tool_q(0, 0, TOP - PRESS)), time_step=0.005, near_rigid_threshold=1.0)
    assert rig.time_step == 0.005 and build_rig("weld", hold(tool_q(0, 0, 0.5))).time_step == H
    assert rig.plant.get_sap_near_rigid_threshold() == 1.0
    rig.command(True)
    rig.advance_to(0.3)
    # One entry per step (a chunk's end may add a second one a rounding error away).
    times = [t for t, _, _ in rig.log]
    steps = [t for t, before in zip(times[1:], times) if t - before > 1e-9]
    assert np.allclose(np.diff([0.0] + steps), 0.005, rtol=0, atol=1e-9)
    assert len(steps) == 60 and steps[-1] == pytest.approx(0.3)
    assert rig.state().attached  # suction still works at that step
    for bad in (0.025, 5e-5):
        with pytest.raises(ConfigError) as info:
            build_rig("weld", hold(tool_q(0, 0, 0.5)), time_step=bad)
        assert str(bad) in str(info.value) and "0.02" in str(info.value)
    with pytest.raises(ConfigError, match="near_rigid_threshold must be >= 0, got -1"):
        build_rig("weld", hold(tool_q(0, 0, 0.5)), near_rigid_threshold=-1.0)


# ----------------------------------------------------------------------------
# No attach


@pytest.mark.parametrize("backend", BACKENDS)
def test_no_attach_when_disabled(backend):
    rig = build_rig(backend, hold(tool_q(0, 0, TOP - PRESS)), log=False)
    rig.advance_to(0.4)
    assert rig.cup_part_contacts() > 0
    state = rig.state()
    assert not state.enabled and not state.attached
    if backend == "weld":
        assert rig.held_body() is None


@pytest.mark.parametrize("backend", BACKENDS)
def test_no_attach_when_not_touching(backend):
    rig = build_rig(backend, hold(tool_q(0, 0, TOP + 0.005)), log=False)
    rig.command(True)
    rig.advance_to(0.4)
    assert rig.cup_part_contacts() == 0
    assert rig.state().enabled and not rig.state().attached


def _tilted(tilt_deg: float) -> np.ndarray:
    """The tool tilted about x so that the cup's lowest rim point is PRESS into the part."""
    tilt = math.radians(tilt_deg)
    rim_drop = 0.02 * math.sin(tilt)  # cup radius 0.02
    # The cup face centre is CUP_OFFSET from tool0 along the tilted axis.
    tool0_z = TOP - PRESS + rim_drop + CUP_OFFSET * math.cos(tilt)
    tool0_y = -CUP_OFFSET * math.sin(tilt)
    return np.array([0.0, tool0_y, tool0_z, 0.0, tilt])


@pytest.mark.parametrize("backend", BACKENDS)
def test_no_attach_when_approach_is_30_deg_off(backend):
    rig = build_rig(backend, hold(_tilted(30.0)), log=False)
    rig.command(True)
    rig.advance_to(0.4)
    assert rig.cup_part_contacts() > 0  # it does touch
    assert not rig.state().attached


def test_attach_when_approach_is_10_deg_off():
    rig = build_rig("force", hold(_tilted(10.0)), log=False)
    rig.command(True)
    rig.advance_to(0.2)
    assert rig.state().attached


# ----------------------------------------------------------------------------
# Attach without snapping, hold, release


def _attach_moment(rig: Rig) -> float:
    """When the part starts being held: the check (force) or the sync (weld)."""
    return rig.state().since


@pytest.mark.parametrize("backend", BACKENDS)
def test_attach_does_not_snap_an_offset_yawed_part(backend):
    # Part yawed 20 deg, the cup 4 cm off its centre (diagonal), pressed 2 mm.
    rig = build_rig(backend, hold(tool_q(0.03, -0.0265, TOP - PRESS)),
                    parts=[(0.0, 0.0, math.radians(20.0))])
    rig.advance_to(0.3)  # the arm has arrived; then suction on
    rig.command(True)
    rig.advance_to(0.6)
    state = rig.state()
    assert state.attached
    t_attach = _attach_moment(rig)
    before, _ = logged_at(rig, t_attach)
    # The first plant step after the attach (its times need not be multiples of the step).
    after = next(X_WP for t, X_WP, _ in rig.log if t > t_attach + 1e-9)
    dist, angle = pose_change(before, after)
    assert dist < 1e-4 and angle < 0.1
    # No jump on any step around it either (the part only settles slowly under the cup).
    window = [X_WP for t, X_WP, _ in rig.log if abs(t - t_attach) <= 0.1 + 1e-9]
    for X_a, X_b in zip(window, window[1:]):
        dist, angle = pose_change(X_a, X_b)
        assert dist < 1e-5 and angle < 0.01
    # The captured pose is the one found (offset and yaw kept).
    p_CP = state.X_CP.translation()
    assert math.hypot(p_CP[0], p_CP[1]) == pytest.approx(0.04, abs=1e-3)
    R_WP_expected = rig.X_WC().rotation() @ state.X_CP.rotation()
    assert pose_change(RigidTransform(R_WP_expected, [0, 0, 0]),
                       RigidTransform(rig.X_WP().rotation(), [0, 0, 0]))[1] < 0.1


@pytest.mark.parametrize("backend, reaction, time_step, max_drift, max_angle", [
    ("weld", False, None, 1e-3, 0.5),
    # The force backend's spring is explicit, its gains capped at m / h^2 (SuctionConfig):
    # 0.8 mm at 5 ms; at the default 10 ms a 1 kg part sags 2.8 mm and tilts 0.50 deg
    # under 20 m/s^2 (pressed 0.1 s before the attach).
    ("force", False, 0.005, 1e-3, 0.5),
    ("force", True, 0.005, 1e-3, 0.5),
    ("force", False, None, 3.5e-3, 0.6),
])
def test_holds_a_1kg_part_through_a_fast_move_then_releases(backend, reaction, time_step, max_drift,
                                                             max_angle):
    """At 1 m/s, 20 m/s^2 ramps. (The rig's tool is SAP-PD driven, so the force
    backend's reaction on the cup is stable here.)"""
    motion, t_moving, t_stop = pick_motion(accel=20.0)
    rig = build_rig(backend, motion, mass=1.0, time_step=time_step,
                    config=SuctionConfig(backend=backend, apply_reaction=reaction))
    rig.command(True)
    rig.advance_to(t_moving)
    state = rig.state()
    assert state.attached
    X_CP = state.X_CP
    drift = []

    def measure(r: Rig) -> None:
        drift.append(pose_change(X_CP, r.X_WC().InvertAndCompose(r.X_WP())))

    rig.advance_to(t_stop + 0.2, after=measure)
    # Peak speed reached 1 m/s.
    speeds = [np.linalg.norm(b[2].translation() - a[2].translation()) / rig.time_step
              for a, b in zip(rig.log, rig.log[1:])]
    assert max(speeds) == pytest.approx(1.0, rel=0.05)
    # Every step, not only at chunk ends.
    steps = [pose_change(X_CP, X_WC.InvertAndCompose(X_WP))
             for t, X_WP, X_WC in rig.log if t >= t_moving]
    worst = max(d for d, _ in steps)
    worst_angle = max(a for _, a in steps)
    assert rig.state().attached
    assert worst < max_drift and worst_angle < max_angle, (worst, worst_angle)
    # The part went up with the tool.
    assert rig.X_WP().translation()[2] > PART_Z + 0.25

    # Release: it falls from where it is and lands on the floor.
    z_held = rig.X_WP().translation()[2]
    rig.command(False)
    # Released at the next plant step (10 ms) and, for the weld, the chunk's sync after
    # it (50 ms): within 0.06 s, so after 0.15 s it has fallen for at least 90 ms (40 mm).
    rig.advance_to(rig.time + 0.15)
    assert not rig.state().attached and rig.state().last_release == "disabled"
    assert rig.X_WP().translation()[2] < z_held - 0.01
    rig.advance_to(rig.time + 1.2)
    p = rig.X_WP().translation()
    assert p[2] == pytest.approx(PART_Z, abs=0.02)
    if backend == "weld":
        assert rig.held_body() is None


def test_force_backend_loses_hold_when_pulled_away():
    """Pressing a held part into the floor stretches the spring: a 'hold lost' release."""
    down = tool_q(0, 0, TOP - PRESS)
    motion = trajectory([(0.0, down), (0.2, down), (0.5, down - [0, 0, 0.03, 0, 0]),
                         (2.0, down - [0, 0, 0.03, 0, 0])])
    rig = build_rig("force", motion, config=SuctionConfig(backend="force", max_hold_distance=0.01),
                    log=False)
    rig.command(True)
    rig.advance_to(0.2)
    assert rig.state().attached
    seen: list[GripperState] = []
    rig.advance_to(0.7, after=lambda r: seen.append(r.state()))
    lost = [s for s in seen if s.last_release == "hold lost"]
    assert lost and all(s.enabled and not s.attached and s.part == "" for s in lost)


def test_connect_spatial_forces_merges_several_force_grippers():
    """Two force grippers share the plant's single applied-force input."""
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(plant_config(), builder)
    parser = Parser(plant)
    cups = []
    for k in (1, 2):
        parser.AddModelsFromString(expand_xacro(
            MODELS_DIR / "vacuum_gripper.urdf.xacro", {"name": f"vacuum_gripper{k}"}), "urdf")
        plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(f"vacuum_gripper{k}_base_link"),
                         RigidTransform([k, 0, 1]))
        cups.append(plant.GetBodyByName(f"vacuum_gripper{k}_cup"))
    parser.AddModelsFromString(expand_xacro(MODELS_DIR / "part.urdf.xacro", {"name": "p"}), "urdf")
    part = plant.GetBodyByName("p")
    plant.Finalize()
    grippers = [add_suction_gripper(builder, plant, cup, [part], SuctionConfig(backend="force"),
                                    f"suction{k}") for k, cup in enumerate(cups, 1)]
    connect_spatial_forces(builder, plant, grippers)
    assert builder.IsConnectedOrExported(plant.get_applied_spatial_force_input_port())
    with pytest.raises(StateError, match="already connected"):
        connect_spatial_forces(builder, plant, grippers)
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    for g in grippers:
        g.GetInputPort("command").FixValue(g.GetMyMutableContextFromRoot(context), [0.0])
    assert plant.get_applied_spatial_force_input_port().Eval(
        plant.GetMyContextFromRoot(context)) == []


def test_gripper_rejects_anchored_parts_and_declares_before_finalize():
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(plant_config(), builder)
    parser = Parser(plant)
    parser.AddModelsFromString(expand_xacro(
        MODELS_DIR / "vacuum_gripper.urdf.xacro", {"name": GRIPPER}), "urdf")
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName(f"{GRIPPER}_base_link"))
    parser.AddModelsFromString(expand_xacro(MODELS_DIR / "part.urdf.xacro", {"name": "p"}), "urdf")
    parser.AddModelsFromString(expand_xacro(MODELS_DIR / "part.urdf.xacro", {"name": "fixed"}), "urdf")
    plant.WeldFrames(plant.world_frame(), plant.GetFrameByName("fixed"), RigidTransform([2, 0, 0]))
    cup = plant.GetBodyByName(f"{GRIPPER}_cup")
    with pytest.raises(ConfigError, match="world body"):
        declare_suction_constraints(plant, cup, plant.world_body())
    plant.Finalize()
    with pytest.raises(StateError, match="before plant.Finalize"):
        declare_suction_constraints(plant, cup, plant.GetBodyByName("p"))
    with pytest.raises(ConfigError, match="'fixed' is anchored"):
        ForceSuctionGripper(plant, cup, [plant.GetBodyByName("fixed")],
                            SuctionConfig(backend="force"), "s")


def test_weld_backend_needs_the_sap_solver():
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(MultibodyPlantConfig(
        time_step=H, discrete_contact_approximation="tamsi", contact_model="point"), builder)
    parser = Parser(plant)
    parser.AddModelsFromString(expand_xacro(
        MODELS_DIR / "vacuum_gripper.urdf.xacro", {"name": GRIPPER}), "urdf")
    parser.AddModelsFromString(expand_xacro(MODELS_DIR / "part.urdf.xacro", {"name": "p"}), "urdf")
    with pytest.raises(ConfigError, match="SAP solver.*tamsi"):
        declare_suction_constraints(plant, plant.GetBodyByName(f"{GRIPPER}_cup"),
                                    plant.GetBodyByName("p"))
