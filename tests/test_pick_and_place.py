"""Pick and place (reference sections 3 and 7): the course's tasks end with parts in bins."""

import json

import numpy as np
import pytest

from omtp_drake import arms
from omtp_drake.errors import ConfigError
from omtp_drake.pick_and_place import Segment, _progress, tool_down
from omtp_drake.tasks import TaskRun, prepare, run_task


def assert_clean_success(result, bin_name, n):
    ledger = result.ledger
    assert result.success, result.to_dict()
    assert ledger.in_bin[bin_name] == n
    assert ledger.on_floor == ledger.on_belt == ledger.disposed == 0
    assert sum(ledger.held.values()) == 0 and ledger.balanced
    assert [p.part for p in result.picks if p.success] == [f"object_{k}" for k in range(1, n + 1)]


def test_assignment4_robot2_places_parts_in_bin1():
    result = run_task("lecture6_assignment4")
    assert_clean_success(result, "bin_1", 2)
    assert all(p.cycle_time < 8.0 for p in result.picks if p.success)


def test_lecture7_robot1_picks_from_the_belt_into_bin2():
    result = run_task("lecture7_conveyor_pick")
    assert_clean_success(result, "bin_2", 2)


def test_fill_bin_ten_parts():
    result = run_task("fill_bin")
    assert_clean_success(result, "bin_1", 10)
    assert result.summary["mean_cycle_time_s"] < 8.0  # bench/bench_fill_bin.py reports it


@pytest.mark.parametrize("seed", range(10))
def test_fill_bin_five_parts_any_seed(seed):
    result = run_task("fill_bin", seed=seed, parts=5)
    assert_clean_success(result, "bin_1", 5)


def test_limits_respected_during_a_run():
    run = TaskRun(prepare("lecture6_assignment4", parts=1))
    rt = run.runtime
    robot = rt.station.arm("robot2")
    plant, tip = robot.control_plant, robot.control_plant.GetFrameByName("vacuum_gripper2_tip")
    context = plant.CreateDefaultContext()
    diffik_context = run._diffik.GetMyContextFromRoot(rt.context)
    peaks = {"joint": np.zeros(6), "tool": 0.0, "commanded": 0.0}
    last = {}

    while not run.done() and rt.time < 20:
        rt.advance(0.005)  # half DiffIK's period: at most one DiffIK step per advance
        v = rt.station.plant.GetVelocities(rt._plant_context, robot.arm)
        q = rt.station.plant.GetPositions(rt._plant_context, robot.arm)
        peaks["joint"] = np.maximum(peaks["joint"], np.abs(v))
        plant.SetPositions(context, q)
        plant.SetVelocities(context, v)
        peaks["tool"] = max(peaks["tool"], float(np.linalg.norm(
            tip.CalcSpatialVelocityInWorld(context).translational())))
        plant.SetPositions(context, run._diffik.get_output_port().Eval(diffik_context))
        p = tip.CalcPoseInWorld(context).translation()
        if "p" in last:  # commanded tool speed: one DiffIK step moves at most 1 m/s x 10 ms
            peaks["commanded"] = max(peaks["commanded"], np.linalg.norm(p - last["p"]) / 0.01)
        last["p"] = p
    assert run.done()
    assert np.all(peaks["joint"] <= np.array(arms.VELOCITY_LIMITS["ur5"])), peaks
    assert peaks["tool"] <= 1.0, peaks  # the arm's real cup-face speed
    # DiffIK's 10 ms steps jitter a little around the plan (which peaks at 0.8 m/s).
    assert peaks["commanded"] <= 1.1, peaks


def test_controller_sees_only_cameras_gripper_and_joints():
    run = TaskRun(prepare("lecture6_assignment4", parts=1))
    controller = run._controller
    names = {controller.get_input_port(i).get_name() for i in range(controller.num_input_ports())}
    assert names == {"camera_image", "bin_camera_image", "gripper_state", "robot_state"}


def test_vacuum_failure_mid_transfer_is_noticed_and_recovered():
    run = TaskRun(prepare("fill_bin", parts=2))
    rt = run.runtime
    while run.status().mode != "TRANSFER":
        rt.advance(0.05)
    rt.advance(0.3)
    rt.fail_vacuum("robot2", 0.5)
    while not run.done() and rt.time < 60:
        rt.advance(0.5)
    picks = run.status().picks
    assert picks[0].reason == "dropped" and not picks[0].success
    assert picks[1].part == picks[0].part and picks[1].success  # re-picked where it fell
    assert rt.ledger().in_bin["bin_1"] == 2


def test_camera_blackout_waits_then_continues():
    run = TaskRun(prepare("fill_bin", parts=1))
    rt = run.runtime
    rt.black_out_camera("logical_camera_2", 2.0)
    rt.advance(1.9)
    assert run.status().mode == "WAIT_PART" and run.status().part == ""
    while not run.done() and rt.time < 20:
        rt.advance(0.5)
    picks = run.status().picks
    assert [p.success for p in picks] == [True] and picks[0].start >= 2.0


def test_paths_are_smooth_and_end_where_asked():
    tau = np.linspace(0, 1, 2001)
    s = np.array([_progress(x) for x in tau])
    v = np.gradient(s, tau)
    assert s[0] == 0 and s[-1] == pytest.approx(1) and abs(v[0]) < 1e-3 and abs(v[-1]) < 1e-3
    assert np.abs(np.diff(v)).max() < 0.01  # no velocity steps
    X0, X1 = tool_down(np.array([1.0, 0.0, 0.5]), 0.0), tool_down(np.array([0.0, 1.0, 0.5]), 1.0)
    arc = Segment("arc", 0.0, 2.0, X0, X1, (0.0, 0.0))
    assert arc.pose(2.0).IsNearlyEqualTo(X1, 1e-9)
    for t in np.linspace(0, 2, 9):  # a level arc of radius 1 about the centre
        p = arc.pose(t).translation()
        assert np.hypot(p[0], p[1]) == pytest.approx(1.0) and p[2] == pytest.approx(0.5)
        assert arc.pose(t).rotation().col(2) == pytest.approx([0, 0, -1])


def test_run_cli_writes_json_and_exit_code(tmp_path, capsys):
    from omtp_drake.cli import main

    path = tmp_path / "result.json"
    assert main(["run", "lecture6_assignment4", "--parts", "1", "--json", str(path), "-q"]) == 0
    data = json.loads(path.read_text())
    assert set(data) == {"scenario", "seed", "picks", "summary", "ledger"}
    assert {"attempted", "succeeded", "failed", "mean_cycle_time_s", "sim_time_s", "wall_time_s",
            "real_time_factor"} <= set(data["summary"])
    assert "SUCCESS" in capsys.readouterr().out
    # Too short to finish: the task failed, exit code 1.
    assert main(["run", "lecture6_assignment4", "--parts", "1", "--duration", "2", "-q"]) == 1


def test_task_errors():
    with pytest.raises(ConfigError, match="has no task"):
        prepare("omtp_factory")
    with pytest.raises(ConfigError, match="--parts must be >= 1"):
        prepare("fill_bin", parts=0)
