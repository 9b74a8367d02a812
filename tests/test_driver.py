"""The driver (omtp_drake.sim.driver): one way to run the cell, world edits between advances,
one function that initialises every Context."""

import math
import re

import numpy as np
import pytest

from omtp_drake.cell.parts import PARK_X0
from omtp_drake.demos import named_pose_tour
from omtp_drake.errors import ConfigError, SimulationError, UnknownNameError
from omtp_drake.scenario import PartConfig, load_scenario
from omtp_drake.sim.deletion_wall import DeletionWall
from omtp_drake.sim.driver import BeltWrap, Driver
from omtp_drake.sim.gripper_events import GripperEvents
from omtp_drake.sim.runtime import FactoryRuntime

REST_Z = 0.92 + 0.1 + 0.001  # belt top + half a 0.2 m part + the 1 mm corner spheres


def test_named_pose_tour_runs_any_scenario_with_parts():
    """Issue 10 bug 2: the tour used to fail on 'suction1.command is not connected'."""
    stats = named_pose_tour("lecture6_assignment4")
    assert stats.sim_time_s > 3.0 and stats.real_time_factor > 0


def test_placed_parts_can_be_removed_and_are_disposed_by_the_wall():
    """Issue 10 bug 3: a part the scenario places is a part like any other."""
    scenario = load_scenario("lecture6_assignment1")  # object_1 placed on the belt
    scenario.spawner = None  # placed parts only (the course's spawner would refill the belt)
    scenario.parts.append(PartConfig(name="crate_1", xyz=[1.2, -4.3, REST_Z]))
    rt = FactoryRuntime(scenario)
    assert rt.parts_in_world() == ["object_1", "crate_1"]
    rt.remove_part("object_1")
    assert rt.parts_in_world() == ["crate_1"]
    assert rt.part_pose("object_1").translation()[0] >= PARK_X0
    with pytest.raises(UnknownNameError, match="unknown part in the world 'object_1'; valid: crate_1"):
        rt.remove_part("object_1")
    rt.set_conveyor_power(100)
    rt.advance_to(4.0)  # crate_1 rides into the deletion wall
    ledger = rt.ledger()
    assert rt.parts_in_world() == [] and ledger.disposed == 2 and ledger.balanced


def test_every_context_is_initialised_by_one_function():
    """The station alone and the runtime start from the same state."""
    from omtp_drake.cell.station import build_station

    rt = FactoryRuntime("lecture6_assignment4", auto_spawn=False)  # nothing spawned at t = 0
    alone = build_station(load_scenario("lecture6_assignment4"))
    states = []
    for station, context in ((alone, alone.create_context()), (rt.station, rt.context)):
        plant_context = station.plant.GetMyContextFromRoot(context)
        assert all(station.part_states.is_parked(plant_context, name) for name in station.pool)
        for gripper in station.grippers.values():
            assert gripper.constraints.held_body(station.plant, plant_context) is None
        states.append(station.plant.GetPositionsAndVelocities(plant_context))
    np.testing.assert_array_equal(states[0], states[1])


def test_the_driver_applies_each_edit_at_its_period():
    rt = FactoryRuntime("lecture7_conveyor")
    edits = {type(e) for e in rt.driver.edits}
    assert {GripperEvents, BeltWrap, DeletionWall} <= edits
    calls = []
    rt.driver.every(0.3, lambda: calls.append(round(rt.time, 9)))
    rt.advance_to(1.0)
    assert calls == [0.3, 0.6, 0.9]
    with pytest.raises(SimulationError, match="cannot go back in time"):
        rt.advance_to(0.5)
    for bad in (math.nan, math.inf):
        with pytest.raises(ConfigError):
            rt.advance_to(bad)
    with pytest.raises(ConfigError, match="period must be a finite time > 0"):
        rt.driver.every(0.0, lambda: None)


def test_auto_spawner_can_be_switched_off_for_a_students_own_spawns():
    rt = FactoryRuntime("lecture6_assignment4", auto_spawn=False)
    rt.advance_to(1.0)
    assert rt.parts_in_world() == []
    name = rt.spawn_part()
    assert name == "object_1" and rt.parts_in_world() == ["object_1"]
    rt.auto_spawn = True
    assert rt.auto_spawn
    with pytest.raises(ConfigError, match="has no spawner"):
        FactoryRuntime("omtp_factory").auto_spawn = True


def test_the_spawner_does_not_look_while_the_part_it_waits_for_sleeps(monkeypatch):
    """fill_bin's spawner (one at a time) waits for its part on the floor: once the part
    sleeps there (it cannot move by itself) the spawner makes no check; removed, the next
    part comes at the next 50 ms check, as when it looked at every one."""
    from omtp_drake.sim.driver import AutoSpawner

    rt = FactoryRuntime("fill_bin")
    rt.advance_to(2.0)
    assert rt.parts_in_world() == ["object_1"] and rt.ledger().parts["object_1"] == "on_floor"
    assert rt.station.part_states.is_asleep(rt.station.plant.GetMyContextFromRoot(rt.context), "object_1")
    checks = []
    check = AutoSpawner.__call__
    monkeypatch.setattr(AutoSpawner, "__call__", lambda s, c: checks.append(c.get_time()) or check(s, c))
    rt.advance_to(3.0)
    assert checks == []
    rt.remove_part("object_1")
    rt.advance_to(3.2)
    assert checks[0] == pytest.approx(3.05) and rt.parts_in_world() == ["object_2"]
    assert rt.part_pose("object_2").translation()[2] < 0.3  # spawned at 3.05 s, fallen since


def test_driver_rejects_an_edit_without_a_period():
    rt = FactoryRuntime("omtp_factory")

    class Broken:
        period = 0.0

        def __call__(self, root_context):
            pass

    with pytest.raises(ConfigError, match="Broken needs a period > 0"):
        Driver(rt.diagram, rt.diagram.CreateDefaultContext(), [Broken()])


def test_ledger_names_where_each_part_is():
    """Issue 11: a part on a stack above a bin's rim is in the bin; a part in the air is
    elsewhere, with its position."""
    scenario = load_scenario("omtp_factory")
    for k, z in enumerate([0.221, 0.422, 0.623]):  # three 0.2 m cubes stacked in bin 1
        scenario.parts.append(PartConfig(name=f"stack_{k}", xyz=[-8.0, -2.2, z]))
    scenario.parts.append(PartConfig(name="flying", xyz=[-6.0, 0.0, 3.0]))
    rt = FactoryRuntime(scenario)
    rt.advance_to(0.3)
    ledger = rt.ledger()
    assert [ledger.parts[f"stack_{k}"] for k in range(3)] == ["in_bin:bin_1"] * 3
    assert rt.part_pose("stack_2").translation()[2] > 0.475 + 0.1  # above the rim
    assert ledger.parts["flying"].startswith("elsewhere:(-6.000, 0.000, 2.")
    assert ledger.elsewhere == 1 and ledger.balanced


@pytest.mark.parametrize(
    "call, words",
    [
        (lambda rt: rt.spawn_part(xyz=[-8.3, -1.2]), "xyz needs 3 finite numbers, got [-8.3, -1.2]"),
        (lambda rt: rt.spawn_part(xyz=[0.0, math.nan, 1.0]), "spawn_part xyz needs 3 finite numbers"),
        (lambda rt: rt.knock_part("object_1", [30.0, 0.0, 0.0]), "of at most 20, got [30.0, 0.0, 0.0]"),
        (lambda rt: rt.move_bin("bin_1", [1.0, 2.0]), "move_bin xyz needs 3 finite numbers, got [1.0, 2.0]"),
    ],
)
def test_services_refuse_a_position_or_velocity_that_is_not_three_finite_numbers(call, words):
    rt = FactoryRuntime("lecture6_assignment4", auto_spawn=False)
    rt.spawn_part()
    before = rt.ledger().parts
    with pytest.raises(ConfigError, match=re.escape(words)):
        call(rt)
    assert rt.ledger().parts == before  # nothing half done


def test_a_parked_part_has_no_contact_geometry_until_it_is_spawned():
    """Parked parts leave SceneGraph's proximity engine (no pose updates, no queries)."""
    from pydrake.geometry import Role

    rt = FactoryRuntime("fill_bin", auto_spawn=False)
    plant = rt.station.plant

    def proximity(name: str) -> list:
        query = plant.get_geometry_query_input_port().Eval(plant.GetMyContextFromRoot(rt.context))
        frame = plant.GetBodyFrameIdOrThrow(plant.GetBodyByName(name, rt.station.parts[name]).index())
        model = rt.station.scene_graph.model_inspector()
        return [
            query.inspector().GetProximityProperties(g) is not None
            for g in model.GetGeometries(frame, Role.kProximity)
        ]

    assert proximity("object_1") == [False] * 9  # the box and its eight corner spheres
    part = rt.spawn_part(xyz=[-7.0, 0.0, 0.3])
    assert part == "object_1" and proximity(part) == [True] * 9
    rt.advance_to(1.0)
    assert rt.part_pose(part).translation()[2] == pytest.approx(0.051, abs=0.002)  # on the floor
    rt.remove_part(part)
    assert proximity(part) == [False] * 9
    assert rt.spawn_part(xyz=[-7.0, 0.0, 0.3]) == "object_2"
    with pytest.raises(SimulationError, match="part 'object_2' is not parked: it is in the world already"):
        rt.station.part_states.unpark(rt.context, "object_2", rt.part_pose("object_2"))
