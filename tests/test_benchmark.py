"""omtp_drake.benchmark: the speed table reports what it measured against the targets."""

import math

import numpy as np
import pytest
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.benchmark import (
    ArmMotion,
    CaseTiming,
    ReplayTiming,
    SpeedReport,
    bare_plant_seconds,
    measure,
    replay_cpu_seconds,
    with_parts,
)
from omtp_drake.cell import arms
from omtp_drake.errors import ConfigError
from omtp_drake.tasks.run import prepare


def test_table_says_which_targets_are_met():
    report = SpeedReport(
        cases=(
            CaseTiming("fast case", bare=0.080, full=0.095, target=0.1),
            CaseTiming("slow case", bare=0.060, full=0.150, target=0.12),
        ),
        station_build_s=0.21,
        task_build_s=0.62,
        cycles=(5.5, 6.2, 7.3),
        repeats=2,
    )
    rows = {line.split("  ")[0].strip(): line for line in report.table().splitlines()}
    assert rows["fast case: wall ms per simulated s (RTF)"].rstrip().endswith("yes")
    assert "95 (10.5)" in rows["fast case: wall ms per simulated s (RTF)"]
    assert "<= 100 (>= 10.0)" in rows["fast case: wall ms per simulated s (RTF)"]
    assert rows["slow case: wall ms per simulated s (RTF)"].rstrip().endswith("NO")
    assert "<= 120 (>= 8.3)" in rows["slow case: wall ms per simulated s (RTF)"]
    assert "150 %" in rows["slow case: bare plant ms/s, our overhead"]  # (150 - 60) / 60
    assert rows["fast case: bare plant ms/s, our overhead"].rstrip().endswith("yes")  # 19 %
    assert "0.21 / 0.62" in rows["diagram build, fill_bin station / with task (s)"]
    assert rows["diagram build, fill_bin station / with task (s)"].rstrip().endswith("NO")
    cycle = rows["pick cycle, fill_bin, 3 picks: mean / worst (s)"]
    assert "6.33 / 7.30" in cycle and cycle.rstrip().endswith("NO")


def test_bare_plant_steps_the_scenario_without_our_systems():
    scenario = prepare("fill_bin")
    seconds = bare_plant_seconds(with_parts(scenario, [[-8.3, -1.23, 0.051]], 0.1), 0.2)
    assert 0 < seconds < 10 and math.isfinite(seconds)


@pytest.mark.parametrize(
    "repeats, bare, message",
    [(0, 10.0, "repeats must be >= 1, got 0"), (1, 0.0, "bare_seconds must be > 0, got 0.0")],
)
def test_bad_settings_are_refused_before_anything_runs(repeats, bare, message):
    with pytest.raises(ConfigError, match=message):
        measure(repeats, bare)


def test_cli_bench_refuses_bad_repeats_in_one_line(capsys):
    from omtp_drake.cli import main

    assert main(["bench", "--repeats", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["omtp-drake: error: repeats must be >= 1, got 0"]


def test_table_reports_the_full_run_over_the_same_motion_replayed():
    report = SpeedReport(
        cases=(),
        station_build_s=0.2,
        task_build_s=0.3,
        cycles=(5.0,),
        repeats=3,
        replays=(ReplayTiming("fill_bin", replay=0.050, full=0.150),),
    )
    rows = {line.split("  ")[0].strip(): line for line in report.table().splitlines()}
    row = rows["fill_bin: CPU ms/s, full / same motion replayed"]
    assert "150 / 50 = 3.00x" in row and row.rstrip().endswith("NO")
    assert "the same run's arm commands replayed" in report.table()


def test_replay_drives_the_bare_plant_with_recorded_commands():
    scenario = with_parts(prepare("fill_bin"), [[-8.3, -1.23, 0.051]], 0.1)
    q0 = np.array(arms.named_pose("Home", scenario.robot("robot2")))
    q1 = q0 + np.array([0.2, 0.0, 0.0, 0.0, 0.0, 0.0])
    hold = PiecewisePolynomial.ZeroOrderHold([-0.005, 0.095, 0.205], np.column_stack([q0, q1, q1]))
    seconds = replay_cpu_seconds(scenario, ArmMotion({"robot2": hold}, 0.2, frozenset({"robot2"})))
    assert 0 < seconds < 10 and math.isfinite(seconds)


def test_replay_follows_the_recorded_run_and_locks_the_arm_that_stood_still():
    """One part of fill_bin at a 2 ms step: the recorded motion names only robot 2 (robot 1's
    command never changed, so the replay locks it as the station does), and the bare plant
    replaying it puts robot 2 where the full run had it (the full run also carries the part)."""
    from pydrake.multibody.plant import MultibodyPlant

    from omtp_drake.benchmark import _bare_simulator, record_arm_motion
    from omtp_drake.tasks.run import run_task

    scenario = prepare("fill_bin", parts=1).with_time_step(0.002)
    motion, result = record_arm_motion(scenario)
    assert result.success and motion.moving == frozenset({"robot2"})
    assert motion.duration == pytest.approx(result.sim_time_s)
    q_full = {}

    def sample(run):
        station = run.runtime.station
        q_full[round(run.runtime.time, 6)] = station.plant.GetPositions(
            station.plant.GetMyContextFromRoot(run.runtime.context), station.arms["robot2"].arm
        )

    run_task(scenario, on_chunk=sample)  # the same seed: the same run again
    bare = with_parts(prepare("fill_bin"), [[-8.3, -1.23, 0.051]], 0.1).with_time_step(0.002)
    simulator, models = _bare_simulator(bare, motion)
    plant = next(s for s in simulator.get_system().GetSystems() if isinstance(s, MultibodyPlant))
    plant_context = plant.GetMyContextFromRoot(simulator.get_context())
    q1 = plant.GetPositions(plant_context, models.arms["robot1"].arm)
    travelled = 0.0
    for t, q in sorted(q_full.items()):
        simulator.AdvanceTo(t)
        q_replay = plant.GetPositions(plant_context, models.arms["robot2"].arm)
        assert np.abs(q_replay - q).max() < 5e-3, t  # 0.0016 rad at most, measured
        travelled = max(travelled, float(np.abs(q - q_full[0.5]).max()))
    assert travelled > 0.5  # the arm went somewhere
    assert np.array_equal(plant.GetPositions(plant_context, models.arms["robot1"].arm), q1)
    joints = [plant.get_joint(i) for i in plant.GetJointIndices(models.arms["robot1"].arm)]
    assert all(joint.is_locked(plant_context) for joint in joints if joint.num_velocities())
