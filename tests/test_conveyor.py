"""Conveyor, break beam, part pool, spawner, deletion wall, ledger (reference section 6)."""

import numpy as np
import pytest

from omtp_drake.cell.conveyor import ConveyorBelt
from omtp_drake.errors import ConfigError, SimulationError
from omtp_drake.scenario import load_scenario
from omtp_drake.sim.runtime import FactoryRuntime

REST_Z = 0.92 + 0.1 + 0.001  # belt top + half a part + the 1 mm corner spheres


def belt_world(pool=3, **spawner):
    s = load_scenario("omtp_factory")
    s.cameras = []
    s.part_pool = pool
    if spawner:
        from omtp_drake.scenario import SpawnerConfig

        s.spawner = SpawnerConfig(**spawner)
    return s


def velocity(rt, name):
    plant = rt.station.plant
    body = plant.GetBodyByName(name)
    return plant.EvalBodySpatialVelocityInWorld(plant.GetMyContextFromRoot(rt.context),
                                                body).translational()


def test_part_rides_the_belt_at_belt_speed():
    """At half and at full power, in one runtime (each a power it is set to)."""
    rt = FactoryRuntime(belt_world())
    on_belt = rt.spawn_part(xyz=[1.2, 0.0, REST_Z])
    on_floor = rt.spawn_part(xyz=[3.0, 0.0, 0.101])
    rt.advance(1.0)  # spawned touching, it settles (less than 1 mm, within 1 s)
    start = rt.part_pose(on_floor).translation()
    for power in (50.0, 100.0):
        rt.set_conveyor_power(power)
        rt.advance(0.5)
        v = velocity(rt, on_belt)
        speed = 0.2 * power / 100
        assert v[1] == pytest.approx(-speed, rel=0.02), power
        assert abs(v[0]) < 1e-4 and abs(rt.part_pose(on_belt).translation()[0] - 1.2) < 1e-4
        rt.advance(0.5)
        np.testing.assert_allclose(rt.part_pose(on_floor).translation(), start, atol=1e-4)
    rt.set_conveyor_power(0)
    rt.advance(0.5)
    assert np.linalg.norm(velocity(rt, on_belt)) < 1e-3


def test_belt_starts_stopped_and_bad_power_is_rejected():
    rt = FactoryRuntime(belt_world())
    assert rt.conveyor_power() == 0.0
    rt.set_conveyor_power(40)
    for bad in (-1, 100.5, float("nan")):
        with pytest.raises(ConfigError, match=r"\[0, 100\]"):
            rt.set_conveyor_power(bad)
    assert rt.conveyor_power() == 40.0


def test_belt_surface_wraps_without_moving_parts():
    rt = FactoryRuntime(belt_world())
    name = rt.spawn_part(xyz=[1.2, 4.0, REST_Z])
    rt.set_conveyor_power(100)
    rt.advance(6.0)
    joint = rt.station.plant.GetJointByName("conveyor_belt_joint")
    assert abs(joint.get_translation(rt.station.plant.GetMyContextFromRoot(rt.context))) < 0.5
    # 6 s at 0.2 m/s (minus the first few ms of acceleration)
    assert rt.part_pose(name).translation()[1] == pytest.approx(4.0 - 1.2, abs=0.01)


def test_lecture7_beam_stops_part_under_camera_and_next_part_arrives():
    rt = FactoryRuntime("lecture7_conveyor")
    assert rt.conveyor_power() == 100.0
    rt.advance_to(4.0)
    detected, distance = rt.break_beam()
    assert detected and 0.1 <= distance <= 0.6
    assert rt.conveyor_power() == 0.0
    assert rt.parts_in_world() == ["object_1"]
    image = rt.camera_image("logical_camera_1")
    assert [m.name for m in image.models if m.type == "object"] == ["object_1"]
    # Still one at a time: nothing else has spawned while object_1 waits.
    rt.advance_to(7.0)
    assert rt.parts_in_world() == ["object_1"]
    rt.remove_part("object_1")
    rt.set_conveyor_power(100)
    rt.advance_to(12.0)
    assert rt.parts_in_world() == ["object_2"]
    assert rt.break_beam()[0] and rt.conveyor_power() == 0.0
    ledger = rt.ledger()
    assert ledger.spawned == 2 and ledger.disposed == 1 and ledger.on_belt == 1 and ledger.balanced


def test_deletion_wall_disposes_and_ledger_balances():
    rt = FactoryRuntime(belt_world(pool=2))
    name = rt.spawn_part(xyz=[1.2, -4.2, REST_Z])
    rt.set_conveyor_power(100)
    for _ in range(8):
        rt.advance(0.5)
        assert rt.ledger().balanced
    ledger = rt.ledger()
    assert ledger.disposed == 1 and ledger.spawned == 1 and ledger.on_belt == 0
    assert name not in rt.parts_in_world()
    assert rt.part_pose(name).translation()[0] > 40  # parked far away
    assert rt.spawn_part(xyz=[1.2, 0.0, REST_Z]) == "object_2"  # then the queue wraps
    assert rt.spawn_part(xyz=[1.2, 1.0, REST_Z]) == name


def test_the_deletion_walls_quick_test_never_misses_a_touch():
    """The wall's check queries SceneGraph only when a part's bounding sphere reaches
    the wall's box: at random poses around the wall (seeded), every touch the query
    finds is flagged, and parts well clear of the wall skip the query."""
    from pydrake.math import RigidTransform, RollPitchYaw

    from omtp_drake.sim.deletion_wall import DeletionWall

    rt = FactoryRuntime(belt_world(pool=1))
    wall = next(e for e in rt.driver.edits if isinstance(e, DeletionWall))
    assert wall._near is not None
    name = rt.spawn_part(xyz=[1.2, 0.0, REST_Z])
    plant = rt.station.plant
    plant_context = plant.GetMyMutableContextFromRoot(rt.context)
    body = plant.GetBodyByName(name, rt.station.parts[name])
    p_WWall = plant.GetBodyByName("deletion_wall").EvalPoseInWorld(plant_context).translation()
    rng = np.random.default_rng(3)
    outcomes = {"touch": 0, "near": 0, "far": 0}
    for _ in range(400):
        p = p_WWall + rng.uniform([-0.25, -0.7, -0.7], [0.25, 0.7, 0.7])
        X_WP = RigidTransform(RollPitchYaw(rng.uniform(-np.pi, np.pi, 3)), p)
        plant.SetFreeBodyPose(plant_context, body, X_WP)
        query = plant.get_geometry_query_input_port().Eval(plant_context)
        touch = any({pair.id_A, pair.id_B} & wall._wall for pair in query.ComputePointPairPenetration())
        near = wall._near.any(plant.GetPositions(plant_context))
        assert near or not touch
        outcomes["touch" if touch else "near" if near else "far"] += 1
    assert min(outcomes.values()) >= 20, outcomes  # all three were tried


def test_empty_pool_is_an_error():
    rt = FactoryRuntime(belt_world(pool=1))
    rt.spawn_part(xyz=[3, 0, 0.101])
    with pytest.raises(SimulationError, match="no parked part left in the pool"):
        rt.spawn_part(xyz=[3, 1, 0.101])


def test_one_at_a_time_refuses_a_second_loose_part():
    rt = FactoryRuntime(belt_world(pool=2, one_at_a_time=True))
    rt.spawn_part(xyz=[3, 0, 0.101])
    with pytest.raises(SimulationError, match="object_1 is still in the world"):
        rt.spawn_part(xyz=[3, 1, 0.101])


def test_spawner_variance_is_seeded():
    def first_pose(seed):
        s = belt_world(pool=1, lateral_variance=0.1, yaw_variance=0.5, period=1.0)
        s.seed = seed
        rt = FactoryRuntime(s)
        return rt.part_pose("object_1").GetAsMatrix4()

    a, b, c = first_pose(1), first_pose(1), first_pose(2)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    assert abs(a[0, 3] - 1.2) <= 0.1


def test_runs_are_deterministic():
    def run():
        rt = FactoryRuntime("lecture7_conveyor")
        rt.advance_to(5.0)
        return np.concatenate([rt.part_pose(n).GetAsMatrix4().ravel() for n in rt.station.parts])

    np.testing.assert_allclose(run(), run(), atol=1e-9, rtol=0)


def test_the_belts_typed_ports_carry_its_power_and_the_servos_desired_state():
    belt = ConveyorBelt(50.0)
    context = belt.CreateDefaultContext()
    assert belt.power_output_port().Eval(context)[0] == 50.0
    np.testing.assert_allclose(belt.desired_state_output_port().Eval(context), [0.0, -0.1])
    assert belt.beam_input_port().size() == 2


def test_break_beam_range_is_the_first_point_of_the_segment_inside_a_part():
    """The beam's slab test against a brute force: points every 0.5 mm along the
    segment [min_range, max_range], the first one inside any part's box (parts put
    at random poses around the beam, seeded)."""
    from pydrake.math import RigidTransform, RollPitchYaw

    rt = FactoryRuntime(belt_world(pool=3))
    names = [rt.spawn_part(xyz=[1.2 + 0.3 * k, -1.0, 0.5]) for k in range(3)]
    beam, plant = rt.station.break_beam, rt.station.plant
    context = beam.GetMyContextFromRoot(rt.context)
    plant_context = plant.GetMyMutableContextFromRoot(rt.context)
    lo, hi = 0.1, 0.6  # the beam's default range
    ts = np.arange(lo, hi + 1e-9, 5e-4)
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(150):
        poses = {}
        for n in names:
            p = beam.p_WE + beam.u_W * rng.uniform(0.0, 0.7) + rng.uniform(-0.15, 0.15, 3)
            poses[n] = RigidTransform(RollPitchYaw(rng.uniform(-np.pi, np.pi, 3)), p)
            plant.SetFreeBodyPose(plant_context, plant.GetBodyByName(n, rt.station.parts[n]), poses[n])
        points = beam.p_WE + ts[:, None] * beam.u_W
        inside = np.zeros(len(ts), bool)
        for X_WP in poses.values():
            p_P = (points - X_WP.translation()) @ X_WP.rotation().matrix()  # rows: points in P
            inside |= np.all(np.abs(p_P) <= 0.1, axis=1)  # 0.2 m cubes, centred frames
        detected, distance = beam.read(context)
        assert bool(detected) == inside.any()
        if inside.any():
            hits += 1
            assert distance == pytest.approx(ts[np.argmax(inside)], abs=6e-4)
        else:
            assert distance == np.inf
    assert 20 < hits < 140  # both outcomes were tried
