"""Batch evaluation on Dask (omtp_drake.batch): the same results as serial runs,
a scheduler reached by its address, faults recorded and retried, resume, bad input.

Every test that runs needs one cluster, the module's (two worker processes): starting a
cluster costs ~6 CPU s (its workers, and each worker's runner importing omtp_drake).

Runs are lecture 6 assignment 4 with one part (~2 s of wall each) or shorter.
"""

import functools
import json
import os
import signal
import time

import pytest

from omtp_drake import batch
from omtp_drake.batch import cluster, plan_batch, run_batch, wilson_interval
from omtp_drake.cli import main
from omtp_drake.errors import ConfigError
from omtp_drake.tasks.run import run_task

SCENARIO = "lecture6_assignment4"


def faulty(scenario, duration):
    """A run function with injected faults: seed 1 aborts its process (as a
    segfault in Drake would), seed 2 raises, seed 3 hangs; others simulate."""
    if scenario.seed == 1:
        os.abort()
    if scenario.seed == 2:
        raise RuntimeError("injected failure")
    if scenario.seed == 3:
        time.sleep(600)
    return batch.simulate(scenario, duration)


def only_seed_0(scenario, duration):
    """A run function for the resume test: any run but seed 0's is an error."""
    if scenario.seed != 0:
        raise AssertionError(f"seed {scenario.seed} should have been skipped")
    return batch.simulate(scenario, duration)


def kill_the_worker_once(scenario, duration, *, marker):
    """A run function whose first call kills the Dask worker running it (SIGKILL, as
    the out-of-memory killer would); Dask then runs it again on another worker."""
    if not os.path.exists(marker):
        open(marker, "w").close()
        runner = os.getppid()  # the run's process is forked by its worker's runner
        with open(f"/proc/{runner}/stat") as f:
            worker = int(f.read().rsplit(")", 1)[1].split()[1])
        os.kill(worker, signal.SIGKILL)
        time.sleep(60)
    return batch.simulate(scenario, duration)


def _no_cluster(*args, **kwargs):
    raise AssertionError("a cluster was started")


@pytest.fixture(scope="module")
def local_client():
    """A client of a LocalCluster of two worker processes (shared: starting one costs seconds)."""
    with batch.connect(workers=2) as client:
        yield client


def test_cluster_runs_equal_serial_runs(local_client, tmp_path):
    settings = {"spawner.yaw_variance": [0.3], "task.max_tool_speed": [0.8, 1.0]}
    out = tmp_path / "batch"
    plan = plan_batch(SCENARIO, [0, 1], settings=settings, parts=1)
    # One after the other: run beside the batch's thread, the serial runs' Drake objects were
    # once garbage-collected in that thread, mid-plot, while this one simulated (CI: SIGABRT).
    records = run_batch(
        SCENARIO, [0, 1], settings=settings, parts=1, client=local_client, out=out, progress=False
    )
    assert [(r.seed, r.settings) for r in records] == [(s.seed, s.settings) for s in plan.runs]
    assert all(r.status == "finished" and r.attempts == 1 for r in records)
    assert len({r.worker for r in records}) == 2  # both worker processes took runs
    # The first run submitted (a worker's first, in a child of its new runner) against the same
    # run in this process: the workers are forks of one server, alike (each serial run costs
    # about 1.3 CPU s; the other records are checked against each other below).
    record, expected = records[0], run_task(plan.runs[0].scenario())
    assert [p.to_dict() for p in record.result.picks] == [p.to_dict() for p in expected.picks]
    assert record.result.ledger == expected.ledger
    assert (record.success, record.result.sim_time_s) == (expected.success, expected.sim_time_s)
    # The seeds differ (spawn yaw), and so do the settings (tool speed).
    assert len({r.result.picks[0].end for r in records}) >= 3
    rows = (out / "runs.csv").read_text().splitlines()
    assert len(rows) == 5 and "task.max_tool_speed" in rows[0]
    summary = json.loads((out / "summary.json").read_text())
    assert [s["settings"]["task.max_tool_speed"] for s in summary] == [0.8, 1.0]
    assert all(s["runs"] == 2 for s in summary)
    assert (out / "success_rate.png").stat().st_size > 0 and (out / "cycle_times.png").stat().st_size > 0


def test_batch_on_a_dask_scheduler_and_workers(local_client, tmp_path, capsys):
    """``omtp-drake batch --scheduler ADDRESS``: the runs go to the workers of the cluster
    whose scheduler is there (the module's: a cluster of its own, scheduler and worker
    started with the `dask` command line, cost ~5.5 CPU s more and tested Dask's commands)."""
    address = local_client.scheduler.address
    workers = set(local_client.scheduler_info()["workers"])
    out = tmp_path / "remote"
    argv = ["batch", SCENARIO, "--seeds", "0:2", "--parts", "1", "--duration", "1.0"]
    code = main([*argv, "--scheduler", address, "--out", str(out), "-q"])
    assert code == 1  # one simulated second is too short to place a part: finished, not successful
    records = [json.loads(p.read_text()) for p in sorted((out / "runs").glob("*.json"))]
    assert [r["seed"] for r in records] == [0, 1]
    assert all(r["status"] == "finished" and r["worker"] in workers for r in records)
    assert all(r["summary"]["sim_time_s"] == pytest.approx(1.0) for r in records)
    printed = capsys.readouterr().out
    assert "defaults:" in printed and "success 0/2" in printed


def test_faults_are_recorded_retried_and_resume_skips_done_runs(local_client, tmp_path, monkeypatch):
    out = tmp_path / "faults"
    kwargs = dict(parts=1, duration=0.5, out=out, progress=False)
    # The runs that end first, under a timeout they never reach (a finished 0.5 s run takes
    # 0.8-1.8 s, 4.9 s pinned to one core beside a busy loop); then, in the same folder, the
    # hang (seed 3) alone, the others read back: its timeout can be short, as no run that must
    # finish shares it. It is reached twice (the run is retried): this test's length.
    run_batch(SCENARIO, [0, 1, 2, 4], client=local_client, timeout=30.0, run_fn=faulty, **kwargs)
    records = run_batch(SCENARIO, range(5), client=local_client, timeout=1.0, run_fn=faulty, **kwargs)
    by_seed = {r.seed: r for r in records}
    assert {s: r.status for s, r in by_seed.items()} == {
        0: "finished",
        1: "crashed",
        2: "error",
        3: "timeout",
        4: "finished",
    }
    assert "SIGABRT" in by_seed[1].message
    assert "RuntimeError: injected failure" in by_seed[2].message
    assert "timeout of 1 s" in by_seed[3].message
    assert [r.resumed for r in records] == [True, True, True, False, True]
    for seed in (1, 2, 3):  # retried once, on the other worker
        record = by_seed[seed]
        assert record.attempts == 2 and record.result is None
        assert record.failed_attempts[0]["status"] == record.status
        assert record.failed_attempts[0]["worker"] != record.worker
    for seed in (0, 4):
        assert by_seed[seed].result.sim_time_s == pytest.approx(0.5) and by_seed[seed].attempts == 1
    saved = json.loads((out / "runs" / "seed1.json").read_text())
    assert saved["status"] == "crashed" and saved["attempts"] == 2

    # Resume: only the run whose JSON is gone runs again; the others are read back.
    (out / "runs" / "seed0.json").unlink()
    resumed = run_batch(SCENARIO, range(5), client=local_client, run_fn=only_seed_0, **kwargs)
    assert [r.status for r in resumed] == ["finished", "crashed", "error", "timeout", "finished"]
    assert resumed[0].result.ledger == by_seed[0].result.ledger
    # Everything done: no cluster at all.
    monkeypatch.setattr(cluster, "connect", _no_cluster)
    again = run_batch(SCENARIO, range(5), workers=2, run_fn=only_seed_0, **kwargs)
    assert [r.to_dict() for r in again] == [r.to_dict() for r in resumed]


def test_a_batch_sweeps_a_faults_time_and_records_each_one(local_client, tmp_path):
    """A fault's field is a setting like any other (tests/test_faults.py has the faults; here
    on the module's cluster: a cluster of its own cost ~4 CPU s)."""
    scenario = tmp_path / "dark.yaml"
    scenario.write_text(
        "base: lecture6_assignment4\n"
        "faults:\n"
        "  - {name: dark, kind: camera_blackout, camera: logical_camera_2, at: 2.0, duration: 0.5}\n"
    )
    records = run_batch(
        str(scenario),
        [0],
        parts=1,
        duration=1.0,  # each swept time falls inside the run; a longer one adds nothing
        settings={"faults.dark.at": [0.25, 0.75]},
        client=local_client,
        out=tmp_path / "out",
        progress=False,
    )
    struck = sorted((r.settings["faults.dark.at"], r.result.faults[0]["time"]) for r in records)
    assert struck == [(0.25, 0.25), (0.75, 0.75)]
    saved = json.loads(next((tmp_path / "out" / "runs").glob("*.json")).read_text())
    assert saved["faults"][0]["name"] == "dark"


@pytest.mark.parametrize(
    "args, message",
    [
        (["--seeds", "0:0"], "--seeds '0:0' is an empty range; valid: START:STOP"),
        (["--seeds", "5:2"], "--seeds '5:2' is an empty range"),
        (["--seeds", "a:b"], "--seeds 'a:b' is malformed"),
        (
            ["--seeds", "0:2", "--set", "task.max_tool_sped=0.5"],
            "unknown key 'max_tool_sped' in task (closest: ",
        ),
        (["--seeds", "0:2", "--set", "task.max_tool_speed=0.6,fast"], "must be a number, got 'fast'"),
        (["--seeds", "0:2", "--set", "task.max_tool_speed=0.6,1.5"], "max_tool_speed must be in (0, 1] m/s"),
        (
            ["--seeds", "0:2", "--set", "cameras.logical_camera_9.position_noise_sigma=0"],
            "no cameras item 'logical_camera_9' (closest: logical_camera_2); names: logical_camera_1, ",
        ),
        (["--seeds", "0:2", "--workers", "0"], "--workers must be an integer >= 1, got 0"),
    ],
)
def test_bad_input_is_one_error_before_anything_starts(args, message, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(cluster, "connect", _no_cluster)
    out = tmp_path / "never"
    assert main(["batch", SCENARIO, *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("omtp-drake: error: ") and message in err and err.count("\n") == 1
    assert not out.exists()


def test_resume_refuses_another_batchs_folder(tmp_path, monkeypatch):
    out = tmp_path / "other"
    out.mkdir()
    (out / "batch.json").write_text(json.dumps({"scenario": "fill_bin", "parts": 3, "fingerprint": "x"}))
    monkeypatch.setattr(cluster, "connect", _no_cluster)
    with pytest.raises(ConfigError, match="holds a batch of another scenario"):
        run_batch(SCENARIO, [0], parts=1, out=out, progress=False)


def test_wilson_interval():
    assert wilson_interval(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert wilson_interval(10, 10) == pytest.approx((0.7225, 1.0), abs=1e-4)
    assert wilson_interval(5, 10) == pytest.approx((0.2366, 0.7634), abs=1e-4)


def test_a_part_given_up_with_its_position_is_not_a_ledger_anomaly_and_survives_json():
    from omtp_drake.control.pick_and_place import PickFailure, PickRecord
    from omtp_drake.sim.ledger import Ledger
    from omtp_drake.tasks.run import TaskResult

    ledger = Ledger(time=30.0, spawned=2, parked=0, on_belt=0, on_floor=1, elsewhere=0, held={"robot2": 0},
                    in_bin={"bin_1": 1}, disposed=0,
                    parts={"object_1": "in_bin:bin_1", "object_2": "on_floor"})
    picks = [PickRecord("object_1", 0.5, 6.0, True),
             PickRecord("object_2", 6.5, 12.0, False, PickFailure.LOST, 1, position=(-7.0, 1.5, 0.05),
                        given_up=True)]
    result = TaskResult(SCENARIO, 3, picks, ledger, False, 30.0, 3.0, "bin_1", 2)
    record = batch.RunRecord(SCENARIO, 3, {}, "finished", result=result)
    assert not record.ledger_anomaly
    again = batch.RunRecord.from_dict(json.loads(json.dumps(record.to_dict())))
    assert not again.ledger_anomaly and again.result.picks[1].position == (-7.0, 1.5, 0.05)
    unrecorded = batch.RunRecord(SCENARIO, 3, {}, "finished", result=TaskResult(
        SCENARIO, 3, picks[:1], ledger, False, 30.0, 3.0, "bin_1", 2))
    assert unrecorded.ledger_anomaly


def test_a_run_whose_worker_dies_is_run_again_and_says_so(local_client, tmp_path, capsys):
    """On the module's cluster (a new one costs ~10 CPU s): its nanny starts the killed worker
    again."""
    out = tmp_path / "lost"
    run_fn = functools.partial(kill_the_worker_once, marker=str(tmp_path / "killed"))
    [record] = run_batch(SCENARIO, [0], parts=1, duration=0.3, client=local_client, out=out, progress=False,
                         run_fn=run_fn)
    assert record.status == "finished" and record.result.sim_time_s == pytest.approx(0.3)
    assert (record.lost_workers, record.attempts, record.retries) == (1, 1, 1)
    saved = json.loads((out / "runs" / "seed0.json").read_text())
    assert (saved["lost_workers"], saved["retries"]) == (1, 1)
    [summary] = batch.summarize([record])
    assert (summary.retries, summary.lost_workers) == (1, 1)
    assert "retries 1 (workers lost 1)" in batch.format_summary([summary])
    # Run again on the same folder: nothing runs, and the CLI says how many were skipped.
    argv = ["batch", SCENARIO, "--seeds", "0:1", "--parts", "1", "--duration", "0.3", "--out", str(out), "-q"]
    code = main(argv)
    assert code == 1  # 0.3 s places no part
    assert "resumed: 1 of 1 runs were done already" in capsys.readouterr().out
