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
        station_build_s=0.21, task_build_s=0.62, cycles=(5.5, 6.2, 7.3), repeats=2)
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


@pytest.mark.parametrize("repeats, bare, message", [(0, 10.0, "repeats must be >= 1, got 0"),
                                                    (1, 0.0, "bare_seconds must be > 0, got 0.0")])
def test_bad_settings_are_refused_before_anything_runs(repeats, bare, message):
    with pytest.raises(ConfigError, match=message):
        measure(repeats, bare)


def test_cli_bench_refuses_bad_repeats_in_one_line(capsys):
    from omtp_drake.cli import main

    assert main(["bench", "--repeats", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["omtp-drake: error: repeats must be >= 1, got 0"]


def test_table_reports_the_full_run_over_the_same_motion_replayed():
    report = SpeedReport(cases=(), station_build_s=0.2, task_build_s=0.3, cycles=(5.0,), repeats=3,
                         replays=(ReplayTiming("fill_bin", replay=0.050, full=0.150),))
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

