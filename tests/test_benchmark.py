"""The speed benchmark (bench/speed.py, behind ``omtp-drake bench``): the table reports
what it measured against the targets; the bare plant and the replay are what they claim."""

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex
from pydrake.trajectories import PiecewisePolynomial

from omtp_drake.bench_command import speed_module
from omtp_drake.cell import arms
from omtp_drake.cell.station import build_station
from omtp_drake.errors import BenchmarkError, ConfigError
from omtp_drake.tasks.run import prepare

speed = speed_module()
ArmMotion, CaseTiming, ReplayTiming, SpeedReport = (
    speed.ArmMotion, speed.CaseTiming, speed.ReplayTiming, speed.SpeedReport)
measure, with_parts = speed.measure, speed.with_parts


def rows(report):
    return {row.what: row for row in report.rows()}


def test_table_says_which_targets_are_met():
    report = SpeedReport(
        cases=(
            CaseTiming("fast case", bare=0.080, full=0.095, target=0.1),
            CaseTiming("slow case", bare=0.060, full=0.150, target=0.12),
        ),
        station_build_s=0.21, task_build_s=0.62, cycles=(5.5, 6.2, 7.3), repeats=2)
    by_what = rows(report)
    fast = by_what["fast case: wall ms per simulated s (RTF)"]
    slow = by_what["slow case: wall ms per simulated s (RTF)"]
    assert (fast.measured, fast.target, fast.met) == ("95 (10.5)", "<= 100 (>= 10.0)", True)
    assert (slow.target, slow.met) == ("<= 120 (>= 8.3)", False)
    assert report.cases[1].overhead == pytest.approx(1.5)  # (150 - 60) / 60
    slow_overhead = by_what["slow case: bare plant ms/s, our overhead"]
    assert (slow_overhead.measured, slow_overhead.met) == ("60, 150 %", False)
    assert by_what["fast case: bare plant ms/s, our overhead"].met  # 19 %
    build = by_what["diagram build, fill_bin station / with task (s)"]
    assert (build.measured, build.met) == ("0.21 / 0.62", False)
    cycle = by_what["pick cycle, fill_bin, 3 picks: mean / worst (s)"]
    assert (cycle.measured, cycle.met) == ("6.33 / 7.30", False)
    assert [line.split()[0] for line in report.table().splitlines()[2:4]] == ["fast", "slow"]


def test_bare_plant_steps_the_scenario_without_our_systems():
    """The bare plant has the full station's bodies, none of our Python systems (only
    pydrake's C++ ones), reaches the time asked, and holds the arms and the part still."""
    scenario = with_parts(prepare("fill_bin"), [[-8.3, -1.23, 0.051]], 0.1)
    simulator, models = speed.bare_simulator(scenario)
    systems = simulator.get_system().GetSystems()
    assert [s for s in systems if not type(s).__module__.startswith("pydrake")] == []
    plant = next(s for s in systems if isinstance(s, MultibodyPlant))
    station = build_station(scenario)

    def bodies(p):
        return sorted(p.get_body(BodyIndex(i)).scoped_name().to_string() for i in range(p.num_bodies()))

    assert bodies(plant) == bodies(station.plant)
    context = plant.GetMyContextFromRoot(simulator.get_context())
    q_arms = {name: plant.GetPositions(context, h.arm) for name, h in models.arms.items()}
    simulator.AdvanceTo(0.2)
    assert simulator.get_context().get_time() == pytest.approx(0.2)
    for name, handles in models.arms.items():
        assert np.abs(plant.GetPositions(context, handles.arm) - q_arms[name]).max() < 1e-3, name
    p_part = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName("bench_0")).translation()
    assert p_part == pytest.approx([-8.3, -1.23, 0.05], abs=2e-3)


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
    row = rows(report)["fill_bin: CPU ms/s, full / same motion replayed"]
    assert report.replays[0].ratio == pytest.approx(3.0)
    assert (row.measured, row.target, row.met) == ("150 / 50 = 3.00x", "<= 1.5x", False)
    assert "the same run's arm commands replayed" in report.table()
    assert "fill_bin: wall ms/s, full / same motion replayed" not in rows(report)  # none measured


def test_table_has_the_wall_ratio_and_a_row_per_profile_part():
    report = SpeedReport(
        cases=(), station_build_s=0.2, task_build_s=0.3, cycles=(5.0,), repeats=1,
        replays=(ReplayTiming("fill_bin", replay=0.020, full=0.028, replay_wall=0.025, full_wall=0.040),),
        profile=(("our Python", 0.04), ("simulator overhead", 0.12), ("DiffIK", 0.2)),
        profile_note="(profile: 100 samples)")
    table = rows(report)
    wall = table["fill_bin: wall ms/s, full / same motion replayed"]
    assert (wall.measured, wall.target, wall.met) == ("40 / 25 = 1.60x", "<= 1.5x", False)
    assert table["fill_bin: CPU ms/s, full / same motion replayed"].met
    ours = table["fill_bin profile (py-spy, of the run): our Python"]
    sim = table["fill_bin profile (py-spy, of the run): simulator overhead"]
    diffik = table["fill_bin profile (py-spy, of the run): DiffIK"]
    assert (ours.measured, ours.target, ours.met) == ("4.0 %", "<= 5 %", True)
    assert (sim.measured, sim.target, sim.met) == ("12.0 %", "<= 8 %", False)
    assert (diffik.target, diffik.met) == ("", True)
    assert "(profile: 100 samples)" in report.table()


def test_profile_split_counts_the_run_and_prints_the_build_apart(tmp_path):
    """A raw py-spy file: samples under the driver's advance_to are the run's, split into
    the parts; the rest of run_task is the build."""
    splitter = speed._profile_split_module()
    run = "run_task (omtp_drake/tasks/run.py:300);advance_to (x/omtp_drake/sim/driver.py:380)"
    raw = tmp_path / "p.raw"
    raw.write_text(
        f"{run};drake::multibody::SapSolver<double>::SolveWithGuess 3\n"
        f"{run};_check (x/omtp_drake/cell/suction.py:10) 1\n"
        "run_task (omtp_drake/tasks/run.py:300);build_station (x/omtp_drake/cell/station.py:1) 5\n"
        "<module> (x.py:1) 7\n"
    )
    samples, totals, build = splitter.split(str(raw))
    assert (samples, build) == (4, 5)
    assert (totals["contact solve"], totals["our Python"]) == (3, 1)



def test_profile_split_counts_our_python_by_module(tmp_path):
    """Our Python's samples go to the module of the innermost frame of ours; a sample
    with Drake below ours is Drake's, and the build is not the run's."""
    splitter = speed._profile_split_module()
    run = "run_task (omtp_drake/tasks/run.py:300);advance_to (x/omtp_drake/sim/driver.py:380)"
    raw = tmp_path / "p.raw"
    raw.write_text(
        f"{run};__call__ (x/omtp_drake/sim/part_sleep.py:90);locked (x/omtp_drake/cell/parts.py:200) 2\n"
        f"{run};_check (x/omtp_drake/cell/suction.py:10) 1\n"
        f"{run};_check (x/omtp_drake/cell/suction.py:10);drake::geometry::QueryObject<double>::X 4\n"
        "run_task (omtp_drake/tasks/run.py:300);build_station (x/omtp_drake/cell/station.py:1) 5\n"
    )
    assert splitter.ours_by_module(str(raw)) == {"cell.parts": 2, "cell.suction": 1}

def test_replay_drives_the_bare_plant_with_recorded_commands():
    """Robot 2 commanded from Home to Home + 0.2 rad on its pan joint at 0.1 s: the bare
    plant replaying that starts at Home and settles on the new command; robot 1, whose
    command the motion does not name as moving, is locked where it stood."""
    scenario = with_parts(prepare("fill_bin"), [[-8.3, -1.23, 0.051]], 0.1)
    q0 = np.array(arms.named_pose("Home", scenario.robot("robot2")))
    q1 = q0 + np.array([0.2, 0.0, 0.0, 0.0, 0.0, 0.0])
    hold = PiecewisePolynomial.ZeroOrderHold([-0.005, 0.095, 1.005], np.column_stack([q0, q1, q1]))
    motion = ArmMotion({"robot2": hold}, 1.0, frozenset({"robot2"}))
    simulator, models = speed.bare_simulator(scenario, motion)
    plant = next(s for s in simulator.get_system().GetSystems() if isinstance(s, MultibodyPlant))
    context = plant.GetMyContextFromRoot(simulator.get_context())
    robot1, robot2 = models.arms["robot1"].arm, models.arms["robot2"].arm
    q_robot1 = plant.GetPositions(context, robot1)
    assert np.abs(plant.GetPositions(context, robot2) - q0).max() < 1e-9
    simulator.AdvanceTo(0.09)
    assert np.abs(plant.GetPositions(context, robot2) - q0).max() < 1e-3  # before the step
    simulator.AdvanceTo(motion.duration)
    assert np.abs(plant.GetPositions(context, robot2) - q1).max() < 2e-3  # the new command
    assert np.array_equal(plant.GetPositions(context, robot1), q_robot1)


def test_a_measured_run_that_fails_is_a_benchmark_error(monkeypatch):
    """A full run that does not succeed times nothing: BenchmarkError, which the CLI
    reports in one line, not a traceback."""
    failed = SimpleNamespace(success=False, summary="0/10 parts in bin_1")
    monkeypatch.setattr(speed, "run_task", lambda scenario: failed)
    with pytest.raises(BenchmarkError, match=r"fill_bin did not succeed in the benchmark: 0/10 parts"):
        speed.task_seconds("fill_bin")


def test_replay_follows_the_recorded_run_and_locks_the_arm_that_stood_still(monkeypatch):
    """One part of fill_bin at a 2 ms step: the recorded motion names only robot 2 (robot 1's
    command never changed, so the replay locks it as the station does), and the bare plant
    replaying it puts robot 2 where the full run had it (the full run also carries the part)."""
    import functools

    from omtp_drake.tasks.run import run_task

    q_full = {}

    def sample(run):
        station = run.runtime.station
        q_full[round(run.runtime.time, 6)] = station.plant.GetPositions(
            station.plant.GetMyContextFromRoot(run.runtime.context), station.arms["robot2"].arm)

    # robot 2's joints sampled after each chunk of the very run that is recorded (on_chunk only
    # reads; the chunks are the same with or without it): one run, not the same run twice.
    monkeypatch.setattr(speed, "run_task", functools.partial(run_task, on_chunk=sample))
    scenario = prepare("fill_bin", parts=1).with_time_step(0.002)
    motion, result = speed.record_arm_motion(scenario)
    assert result.success and motion.moving == frozenset({"robot2"})
    assert motion.duration == pytest.approx(result.sim_time_s)
    assert max(q_full) == pytest.approx(result.sim_time_s)  # sampled to the run's end
    bare = with_parts(prepare("fill_bin"), [[-8.3, -1.23, 0.051]], 0.1).with_time_step(0.002)
    simulator, models = speed.bare_simulator(bare, motion)
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


def test_peer_rows_compare_our_fill_bin_with_each_engine():
    report = SpeedReport(
        cases=(), station_build_s=0.2, task_build_s=0.3, cycles=(5.5,), repeats=1,
        replays=(ReplayTiming("fill_bin", replay=0.021, full=0.054),),
        peers=(("PyBullet", 0.025, 1.3), ("MuJoCo", 0.060, 1.5)))
    by_what = rows(report)
    pybullet = by_what["fill_bin against PyBullet at its defaults: CPU ms/s, ours / its"]
    mujoco = by_what["fill_bin against MuJoCo at its defaults: CPU ms/s, ours / its"]
    assert (pybullet.measured, pybullet.target, pybullet.met) == ("54 / 25 = 2.16x", "<= 1.3x", False)
    assert (mujoco.measured, mujoco.met) == ("54 / 60 = 0.90x", True)
    note = "no peer rows: pybullet is not installed (pip install -e '.[bench]')"
    assert note in replace(report, peers=(), peer_note=note).table()


def test_replay_with_parts_carries_the_runs_part_into_the_bin():
    """fill_bin with one part: the recording notes the run's edits of its part (spawned,
    asleep on the floor, woken, held by robot 2's cup, let go over the bin), and the bare
    plant replaying the arm motion with those edits has the part asleep where the run's
    was (the same physics under the same motion) and carries it into bin 1."""
    replay_parts = speed._sibling("replay_parts")
    scenario = prepare("fill_bin", parts=1)
    motion, result = speed.record_arm_motion(scenario)
    assert result.success
    kinds = [(e.kind, e.part) for e in motion.parts]
    assert kinds[0] == ("unpark", "object_1")
    assert ("sleep", "object_1") in kinds
    assert [k for k in kinds if k[0] in ("attach", "release")] == [
        ("attach", "object_1"), ("release", "object_1")]
    holds = {}
    simulator, models = speed.bare_simulator(scenario, motion, holds)
    assert set(holds) == {"robot1", "robot2"}
    apart = replay_parts.advance_with_parts(
        simulator, models, holds, list(motion.parts), motion.duration)
    assert simulator.get_context().get_time() == pytest.approx(motion.duration)
    assert apart["object_1"] < 1e-3  # 0.0000 mm measured: the same floats
    plant = next(s for s in simulator.get_system().GetSystems() if isinstance(s, MultibodyPlant))
    context = plant.GetMyContextFromRoot(simulator.get_context())
    body = plant.GetBodyByName("object_1", models.parts["object_1"])
    p_end = plant.EvalBodyPoseInWorld(context, body).translation()
    assert scenario.bin("bin_1").contains(p_end)  # carried, not left on the floor


def test_the_replay_with_parts_row_stands_beside_the_issues_row():
    report = SpeedReport(
        cases=(), station_build_s=0.2, task_build_s=0.3, cycles=(5.5,), repeats=1,
        replays=(ReplayTiming("fill_bin", replay=0.080, full=0.180, replay_parts=0.090),))
    by_what = rows(report)
    issue = by_what["fill_bin: CPU ms/s, full / same motion replayed"]
    carried = by_what["fill_bin: CPU ms/s, full / same motion and parts replayed"]
    assert (issue.measured, issue.target, issue.met) == ("180 / 80 = 2.25x", "<= 1.5x", False)
    assert (carried.measured, carried.target) == ("180 / 90 = 2.00x", "(reference)")
    without = SpeedReport(
        cases=(), station_build_s=0.2, task_build_s=0.3, cycles=(5.5,), repeats=1,
        replays=(ReplayTiming("fill_bin", replay=0.080, full=0.180),))
    assert "fill_bin: CPU ms/s, full / same motion and parts replayed" not in rows(without)
