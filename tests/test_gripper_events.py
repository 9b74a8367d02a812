"""The grippers' events (issue 38): a gripper commanded by services applies the course
plugin's rule only when its command changes or a check is due, with the plugin's timing;
an idle gripper runs no Python; the task robot's gripper polls at its controller's rate."""

import math

import numpy as np
import pytest

from omtp_drake import Cell, tool_down
from omtp_drake.cell.station import build_station
from omtp_drake.cell.suction import CommandPolling, SuctionGripper
from omtp_drake.scenario import load_scenario

SPOT = [-8.3, -1.23, 0.3]  # under logical camera 2 (lecture6_assignment4)


@pytest.fixture(scope="module")
def cell():
    return Cell("lecture6_assignment4", auto_spawn=False)


def _memory(cell, robot="robot2"):
    gripper = cell.runtime.station.grippers[robot]
    return gripper._get_memory(gripper.GetMyContextFromRoot(cell.runtime.context))


def _held_body(cell, robot="robot2"):
    gripper, plant = cell.runtime.station.grippers[robot], cell.runtime.station.plant
    return gripper.constraints.held_body(plant, plant.GetMyContextFromRoot(cell.runtime.context))


def _step_to(cell, t):
    """Advances one plant step at a time to ``t``; returns the gripper's check times seen."""
    h, checks = cell.runtime.station.plant.time_step(), []
    while cell.time < t - 1e-9:
        cell.runtime.advance_to(min(t, (math.floor(cell.time / h + 1e-9) + 1) * h))
        last = _memory(cell).last_check
        if last > -math.inf and (not checks or last > checks[-1] + 1e-9):
            checks.append(last)
    return checks


def test_service_commands_keep_the_plugins_timing_and_the_weld_follows_one_step_later(cell):
    """Enabled between two plant steps with the cup pressed on a part: the first check at
    the next step, the second 0.1 s later decides, the weld is made one step after it; a
    disable between steps releases at the next step (the rule runs as the advance from it
    begins, as the plugin's update) and the constraints hold through that step."""
    arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
    h = cell.runtime.station.plant.time_step()
    arm.go("Home")
    part = cell.spawn_part(xyz=SPOT, yaw=0.0)
    try:
        cell.wait(1.0)
        p = cell.part_pose(part).translation()
        arm.go(tool_down(p + [0, 0, 0.16]), frame="suction_cup")
        cell.wait(0.3 + 0.0037)  # off the plant's step grid
        s = cell.time
        first = math.ceil(s / h - 1e-6) * h
        vacuum.on()
        assert not vacuum.state().enabled  # the rule runs at the next step, not at the call
        checks = _step_to(cell, first + 0.1 + 0.5 * h)
        assert checks == pytest.approx([first, first + 0.1])
        assert not vacuum.attached and _held_body(cell) is None  # decided, not yet made
        _step_to(cell, first + 0.1 + h)
        assert vacuum.attached and vacuum.part == part
        assert vacuum.state().since == pytest.approx(first + 0.1 + h)
        assert _held_body(cell) is not None
        assert _step_to(cell, first + 0.35)[-2:] == pytest.approx([first + 0.2, first + 0.3])
        cell.wait(0.0042)
        s = cell.time
        step = math.ceil(s / h - 1e-6) * h
        vacuum.off()
        _step_to(cell, step)
        assert vacuum.attached and _held_body(cell) is not None
        _step_to(cell, step + h)
        assert not vacuum.attached and vacuum.state().last_release == "disabled"
        assert _held_body(cell) is None
    finally:
        vacuum.off()
        cell.wait(0.5)
        cell.remove_part(part)


def test_an_idle_gripper_runs_no_python(cell, monkeypatch):
    """Neither gripper commanded: a second of simulation runs the rule of neither, nor
    the weld's sync (no weld holds a part: it would find nothing to do)."""
    from omtp_drake.sim import gripper_events

    calls, syncs = [], []
    rule, sync = SuctionGripper._next, gripper_events.sync_weld
    monkeypatch.setattr(SuctionGripper, "_next", lambda self, *a: calls.append(self) or rule(self, *a))
    monkeypatch.setattr(gripper_events, "sync_weld", lambda *a: syncs.append(a) or sync(*a))
    cell.wait(1.0)
    assert calls == [] and syncs == []
    assert all(g.polling is None for g in cell.runtime.station.grippers.values())


def test_the_task_robots_gripper_polls_one_step_after_each_controller_update():
    scenario = load_scenario("fill_bin")
    task = scenario.required_task()
    assert all(g.polling is None for g in build_station(scenario).grippers.values())
    station = build_station(scenario, controlled=[task.robot])
    h = scenario.plant_config.time_step
    polling = station.grippers[task.robot].polling
    assert polling == CommandPolling(1.0 / task.update_rate_hz, h)
    others = [g.polling for robot, g in station.grippers.items() if robot != task.robot]
    assert others and all(p is None for p in others)
    # The polls: 0.01, 0.06, 0.11, ... (the controller updates at 0, 0.05, 0.1, ...).
    from omtp_drake.sim.gripper_events import _poll_at_or_after

    gripper = station.grippers[task.robot]
    np.testing.assert_allclose([_poll_at_or_after(gripper, t) for t in (0.0, 0.01, 0.02, 0.5)],
                               [0.01, 0.01, 0.06, 0.51])


def test_a_gripper_command_written_by_an_undeclared_system_is_refused():
    """A controller wired to a gripper the station built for service commands would
    never be heard: the runtime says so instead of running deaf."""
    from omtp_drake.control.pick_and_place import add_pick_and_place
    from omtp_drake.errors import ConfigError
    from omtp_drake.sim.runtime import FactoryRuntime

    scenario = load_scenario("fill_bin")
    task = scenario.required_task()
    with pytest.raises(ConfigError, match="robot2 is connected to a system of the diagram"):
        FactoryRuntime(scenario, extend=lambda builder, station: add_pick_and_place(builder, station, task))


def test_a_vacuum_failure_drops_at_once_and_the_weld_goes_at_the_next_idle_sync():
    """The task's controller holds a part; the vacuum fails at a tick: the gripper lets go
    at its next poll (its controller's update at the tick still sees the part held, as
    beside the per-step poll), the constraints at the next 50 ms sync, however finely the run is
    advanced (the per-step poll did so in a run advanced by ticks, as the soak's, and one
    step later in one advanced step by step), not at a stop the driver makes for an attach."""
    from omtp_drake.tasks.run import TaskRun, prepare

    run = TaskRun(prepare("fill_bin", seed=0))
    rt = run.runtime
    h = rt.station.plant.time_step()
    gripper, plant = rt.station.grippers["robot2"], rt.station.plant

    def held():
        return gripper.constraints.held_body(plant, plant.GetMyContextFromRoot(rt.context))

    while not rt.gripper_state("robot2").attached:
        rt.advance_to(rt.time + 0.05)
    rt.advance_to(round(rt.time + 0.3, 9))  # lifting, well past the attach
    s = rt.time
    rt.fail_vacuum("robot2", 0.5)
    released = []
    while rt.time < s + 0.1 - 1e-9:
        rt.advance_to(round(rt.time + h, 9))
        if held() is None and not released:
            released.append(rt.time)
        if abs(rt.time - (s + 2 * h)) < 1e-9:  # let go at its poll one step after the tick
            assert not rt.gripper_state("robot2").attached
    assert released == pytest.approx([s + 0.05])


def test_an_attach_decided_where_no_stop_was_announced_is_welded_at_the_next_stop():
    """consecutive_checks: 1 and a run advanced by the controller's ticks: the command
    switches on inside an advance and the first poll decides, so no stop was announced
    for the weld one step later; it is made as the run goes on from the next stop, not
    never (the idle sync no longer runs while nothing is held), and the idle sync then
    runs while it holds: the controller's release lets the part go into the bin."""
    from omtp_drake.tasks.run import TaskRun, prepare

    scenario = prepare("lecture6_assignment4", parts=1)
    scenario.suction.consecutive_checks = 1
    run = TaskRun(scenario)
    rt = run.runtime
    while not rt.gripper_state("robot2").attached and rt.time < 5.0:
        rt.advance(0.05)
    state, decided = rt.gripper_state("robot2"), _memory(run).last_check
    assert state.attached and _held_body(run) is not None, state
    assert decided < state.since <= decided + 0.05 + 1e-9, (decided, state.since)
    while not run.done() and rt.time < 10.0:
        rt.advance(0.05)
    assert run.done() and _held_body(run) is None, run.history().picks
    assert rt.ledger().in_bin["bin_1"] == 1, rt.ledger()
