"""Parts at rest fall asleep (their joints locked, their contacts with what never
moves filtered out) and wake when something that moves touches them
(omtp_drake.cell.rest_clock, omtp_drake.sim.part_sleep)."""

from dataclasses import replace

import pytest
from pydrake.geometry import Role

from omtp_drake.errors import ConfigError
from omtp_drake.scenario import load_scenario
from omtp_drake.sim.driver import world_edits
from omtp_drake.sim.part_sleep import PartSleep
from omtp_drake.sim.runtime import FactoryRuntime
from omtp_drake.tasks.run import TaskRun, prepare

SIZE = 0.1  # fill_bin's parts


def _runtime(**changes) -> FactoryRuntime:
    return FactoryRuntime(replace(load_scenario("fill_bin"), **changes), auto_spawn=False)


def _asleep(rt: FactoryRuntime, name: str) -> bool:
    return rt.station.part_states.is_asleep(rt.station.plant.GetMyContextFromRoot(rt.context), name)


def _over_bin(rt: FactoryRuntime, height: float) -> list[float]:
    p = rt.bin_pose("bin_1").translation()
    return [p[0], p[1], p[2] + height]


def _filtered_against_bin(rt: FactoryRuntime, name: str) -> bool:
    """Whether SceneGraph (in the run's Context) filters every pair of the part's
    collision geometry with bin_1's."""
    station, plant = rt.station, rt.station.plant
    query = plant.get_geometry_query_input_port().Eval(plant.GetMyContextFromRoot(rt.context))
    inspector = query.inspector()

    def geometries(body):
        return inspector.GetGeometries(plant.GetBodyFrameIdOrThrow(body.index()), Role.kProximity)

    part = geometries(plant.GetBodyByName(name, station.parts[name]))
    bin_ = [
        g
        for b in plant.GetBodyIndices(plant.GetModelInstanceByName("bin_1"))
        for g in geometries(plant.get_body(b))
    ]
    assert part and bin_
    return all(inspector.CollisionFiltered(a, b) for a in part for b in bin_)


def _in_proximity_engine(rt: FactoryRuntime, name: str) -> dict[str, int]:
    """How many of the part's box and corner spheres SceneGraph has in its proximity
    engine now (in the run's Context)."""
    plant = rt.station.plant
    query = plant.get_geometry_query_input_port().Eval(plant.GetMyContextFromRoot(rt.context))
    model = rt.station.scene_graph.model_inspector()
    frame = plant.GetBodyFrameIdOrThrow(plant.GetBodyByName(name, rt.station.parts[name]).index())
    counts = {"Box": 0, "Sphere": 0}
    for g in model.GetGeometries(frame, Role.kProximity):
        if query.inspector().GetProximityProperties(g) is not None:
            counts[type(model.GetShape(g)).__name__] += 1
    return counts


def test_a_part_at_rest_in_a_bin_falls_asleep_where_it_lies():
    rt = _runtime()
    part = rt.spawn_part(xyz=_over_bin(rt, 0.4))
    rt.advance_to(0.2)
    assert not _asleep(rt, part)  # falling
    rt.advance_to(2.0)
    assert _asleep(rt, part)
    X_before = rt.part_pose(part)
    rt.advance_to(4.0)
    assert rt.part_pose(part).IsExactlyEqualTo(X_before)  # locked: not a micrometre of drift
    assert rt.parts_in_world() == [part]  # asleep is in the world, not parked
    states, plant_context = rt.station.part_states, rt.station.plant.GetMyContextFromRoot(rt.context)
    parked, asleep = states.locked(plant_context)
    assert asleep == [part] and part not in parked and len(parked) == len(rt.station.pool) - 1
    assert states.parked(plant_context) == parked  # the pool's quicker question, the same answer
    assert rt.ledger().parts == {part: "in_bin:bin_1"}
    assert _filtered_against_bin(rt, part)  # its contact with the bin costs nothing
    assert _in_proximity_engine(rt, part) == {"Box": 1, "Sphere": 0}  # its box alone is touchable


def test_a_part_dropped_onto_a_sleeping_part_wakes_it_and_both_fall_asleep_again():
    scenario = load_scenario("fill_bin")
    rt = _runtime(spawner=replace(scenario.spawner, one_at_a_time=False))
    bottom = rt.spawn_part(xyz=[-7.0, 0.0, 0.2], yaw=0.0)
    rt.advance_to(2.0)
    assert _asleep(rt, bottom)
    # Onto the bottom part's edge: it hits it and bounces off onto the floor.
    top = rt.spawn_part(xyz=list(rt.part_pose(bottom).translation() + [SIZE, 0.0, 0.3]), yaw=0.0)
    states = []
    while rt.time < 5.0:
        rt.advance(0.05)
        states.append(_asleep(rt, bottom))
    assert not all(states), "the falling part never woke the one it hit"
    assert _asleep(rt, bottom) and _asleep(rt, top)
    for part in (bottom, top):
        assert rt.part_pose(part).translation()[2] == pytest.approx(SIZE / 2 + 0.001, abs=0.002)
    assert set(rt.ledger().parts.values()) == {"on_floor"}


def test_a_knocked_sleeping_part_wakes_and_moves():
    rt = _runtime()
    part = rt.spawn_part(xyz=_over_bin(rt, 0.2))
    rt.advance_to(2.0)
    assert _asleep(rt, part)
    p0 = rt.part_pose(part).translation()
    rt.knock_part(part, [0.0, 0.0, 2.0])  # straight up
    assert not _asleep(rt, part) and not _filtered_against_bin(rt, part)
    assert _in_proximity_engine(rt, part) == {"Box": 1, "Sphere": 8}
    rt.advance(0.1)
    assert rt.part_pose(part).translation()[2] > p0[2] + 0.1


def test_a_bin_moved_with_sleeping_parts_carries_them():
    rt = _runtime()
    part = rt.spawn_part(xyz=_over_bin(rt, 0.2))
    rt.advance_to(2.0)
    assert _asleep(rt, part)
    X_BP = rt.bin_pose("bin_1").inverse() @ rt.part_pose(part)
    p = rt.bin_pose("bin_1").translation()
    rt.move_bin("bin_1", [p[0] + 0.5, p[1] - 0.3, p[2]], yaw=0.3)
    rt.advance_to(4.0)
    X_BP_now = rt.bin_pose("bin_1").inverse() @ rt.part_pose(part)
    assert X_BP_now.IsNearlyEqualTo(X_BP, 1e-9)
    assert rt.ledger().parts == {part: "in_bin:bin_1"}


def test_a_sleeping_part_disposed_of_and_spawned_again_rests_on_the_floor():
    """Disposal restores its contacts: spawned again, it lands on the floor, not through it."""
    rt = _runtime(part_pool=1)
    part = rt.spawn_part(xyz=_over_bin(rt, 0.2))
    rt.advance_to(2.0)
    assert _asleep(rt, part)
    rt.remove_part(part)
    assert rt.parts_in_world() == []
    assert rt.spawn_part(xyz=[-7.0, 0.0, 0.3]) == part
    rt.advance_to(4.0)
    assert rt.part_pose(part).translation()[2] == pytest.approx(SIZE / 2, abs=0.004)


def test_the_arm_picks_a_part_that_fell_asleep_on_the_floor():
    """The cup touching a sleeping part wakes it: the pick goes on as if it never slept."""
    run = TaskRun(prepare("fill_bin", parts=1))
    rt = run.runtime
    slept = False
    while not run.done() and rt.time < 20.0:
        rt.advance(0.1)
        slept = slept or any(
            _asleep(rt, n) and rt.ledger().parts[n] == "on_floor" for n in rt.parts_in_world()
        )
    assert slept
    assert run.done() and [p.success for p in run.history().picks] == [True]
    assert list(rt.ledger().parts.values()) == ["in_bin:bin_1"]


def test_with_sleep_disabled_no_part_is_ever_locked():
    scenario = load_scenario("fill_bin")
    rt = _runtime(sleep=replace(scenario.sleep, enabled=False))
    assert rt.station.rest_clock is None
    assert not any(isinstance(e, PartSleep) for e in world_edits(rt.station, rt.pool))
    part = rt.spawn_part(xyz=_over_bin(rt, 0.2))
    rt.advance_to(3.0)
    assert not _asleep(rt, part) and not _filtered_against_bin(rt, part)


@pytest.mark.parametrize(
    "field, value, words",
    [
        ("rest_time", 0.0, "sleep.rest_time must be a finite number > 0, got 0.0"),
        ("linear_speed", -1.0, "sleep.linear_speed must be a finite number > 0, got -1.0"),
        ("angular_speed", float("nan"), "sleep.angular_speed = nan is not a finite number"),
        ("check_rate_hz", 0.0, r"sleep.check_rate_hz must be in \(0, 1000\] Hz, got 0.0"),
    ],
)
def test_a_bad_sleep_setting_is_refused_with_its_name(field, value, words):
    scenario = load_scenario("fill_bin")
    bad = replace(scenario, sleep=replace(scenario.sleep, **{field: value}))
    with pytest.raises(ConfigError, match=words):
        bad.validate()


def test_rest_clock_counts_a_part_still_only_below_both_speeds():
    """Free cubes in zero gravity keep their velocities: the clock (20 Hz from t = 0)
    says still since 0 for those below 0.01 m/s and 0.1 rad/s, moving (inf) otherwise."""
    import math

    from pydrake.multibody.math import SpatialVelocity
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
    from pydrake.multibody.tree import SpatialInertia
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder

    from omtp_drake.cell.rest_clock import RestClock
    from omtp_drake.scenario import SleepConfig

    velocities = {  # name: (w, v), the defaults' limits 0.1 rad/s and 0.01 m/s
        "slow": ([0, 0, 0], [0.0095, 0, 0]),
        "fast": ([0, 0, 0], [0, 0.0105, 0]),
        "spinning": ([0, 0, 0.105], [0, 0, 0]),
        "turning_slowly": ([0.095, 0, 0], [0, 0, 0.0095]),
    }
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=0.01)
    plant.mutable_gravity_field().set_gravity_vector([0, 0, 0])
    parts = {}
    for name in velocities:
        parts[name] = plant.AddModelInstance(name)
        plant.AddRigidBody(name, parts[name], SpatialInertia.SolidCubeWithDensity(1000.0, 0.1))
    plant.Finalize()
    clock = RestClock.AddToDiagram(builder, plant, parts, SleepConfig(check_rate_hz=20.0))
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    for name, (w, v) in velocities.items():
        body = plant.GetBodyByName(name, parts[name])
        plant.SetFreeBodySpatialVelocity(plant_context, body, SpatialVelocity(w, v))
    Simulator(diagram, context).AdvanceTo(0.12)
    since = clock.still_since(clock.GetMyContextFromRoot(context))
    assert since == {"slow": 0.0, "fast": math.inf, "spinning": math.inf, "turning_slowly": 0.0}


def test_a_rest_clock_its_owner_samples_says_what_a_periodic_one_says():
    """The station's clock is sampled by the driver only while some part is free, and
    records once that all are locked: at every sample time it says what a clock sampling
    itself at 20 Hz says, while parts move, all lie locked, and one is freed again."""
    import math

    import numpy as np
    from pydrake.multibody.math import SpatialVelocity
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
    from pydrake.multibody.tree import SpatialInertia
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder

    from omtp_drake.cell.rest_clock import RestClock
    from omtp_drake.scenario import SleepConfig

    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=0.01)
    plant.mutable_gravity_field().set_gravity_vector([0, 0, 0])
    parts = {n: plant.AddModelInstance(n) for n in ("a", "b")}
    for name, instance in parts.items():
        plant.AddRigidBody(name, instance, SpatialInertia.SolidCubeWithDensity(1000.0, 0.1))
    plant.Finalize()
    config = SleepConfig(check_rate_hz=20.0)  # the owner samples every 50 ms below
    periodic = RestClock.AddToDiagram(builder, plant, parts, config)
    owned = builder.AddNamedSystem("owned_clock", RestClock(plant, parts, config, periodic=False))
    builder.Connect(plant.get_state_output_port(), owned.plant_state_input_port())
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    plant_context = plant.GetMyMutableContextFromRoot(context)
    bodies = {n: plant.GetBodyByName(n, i) for n, i in parts.items()}
    joints = {n: plant.get_joint(plant.GetJointIndices(i)[0]) for n, i in parts.items()}
    moving = SpatialVelocity([0, 0, 0], [0.5, 0, 0])
    plant.SetFreeBodySpatialVelocity(plant_context, bodies["a"], moving)
    simulator = Simulator(diagram, context)
    owned_context = owned.GetMyMutableContextFromRoot(context)
    seen = []
    for k in range(40):
        t = 0.05 * k
        simulator.AdvanceTo(t)
        if k == 6:  # both locked (asleep or parked) from 0.3 s
            for joint in joints.values():
                joint.Lock(plant_context)
        if k == 20:  # "a" freed at 1.0 s, moving again, then still from 1.4 s
            joints["a"].Unlock(plant_context)
            plant.SetFreeBodySpatialVelocity(plant_context, bodies["a"], moving)
        if k == 28:
            plant.SetFreeBodySpatialVelocity(plant_context, bodies["a"], SpatialVelocity.Zero())
        if any(not j.is_locked(plant_context) for j in joints.values()):
            owned.sample(owned_context)
        else:
            owned.all_locked_at(owned_context, t)
        seen.append(owned.still_since_values(owned_context).tolist())
        expected = periodic.still_since_values(periodic.GetMyContextFromRoot(context))
        if k > 0:
            np.testing.assert_array_equal(seen[-2], expected)  # what each said before this sample
    assert seen[5] == [math.inf, 0.0] and seen[10] == pytest.approx([0.3, 0.0])
    assert seen[25] == [math.inf, 0.0] and seen[30] == pytest.approx([1.4, 0.0])
