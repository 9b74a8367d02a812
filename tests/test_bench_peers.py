"""The peer cells of bench/bench_peers.py do the job for real: a one-part ``fill_bin`` run of
ours, recorded, replayed in PyBullet and in MuJoCo, leaves the part in the bin; without
suction it stays on the floor (so the count is what happened, not what was commanded)."""

from dataclasses import replace

import numpy as np
import pytest

from omtp_drake.bench_command import bench_module

_EXTRA = 'needs the bench extra (pip install -e ".[bench]"), which the test extra does not include'
pytest.importorskip("pybullet", reason=f"pybullet is not installed: {_EXTRA}")
pytest.importorskip("mujoco", reason=f"mujoco is not installed: {_EXTRA}")

peer_job = bench_module("peer_job")
ENGINES = ("peer_pybullet", "peer_mujoco")


@pytest.fixture(scope="module")
def job():
    """Our fill_bin with one part, recorded (a few simulated seconds)."""
    return peer_job.record_fill_bin(parts=1)


def test_the_recording_holds_our_run(job):
    assert job.in_bin == 1 and len(job.spawns) == 1
    assert job.q.shape == (len(job.times), 6)
    assert np.allclose(np.diff(job.times), 0.01)  # robot 2's servo samples at 100 Hz
    assert job.suction.any() and not job.suction[-1]  # sucked, then let go
    t, xyz, _ = job.spawns[0]
    assert t == 0.0 and xyz[2] == pytest.approx(0.3, abs=0.01)  # the spawner's drop height


@pytest.mark.parametrize("engine", ENGINES)
def test_a_peer_puts_the_part_in_the_bin(job, engine):
    cpu, in_bin, _build = bench_module(engine).run_fill_bin(job)
    assert in_bin == 1 and cpu > 0


@pytest.mark.parametrize("engine", ENGINES)
def test_without_suction_the_part_stays_out_of_the_bin(job, engine):
    _cpu, in_bin, _build = bench_module(engine).run_fill_bin(replace(job, suction=np.zeros_like(job.suction)))
    assert in_bin == 0


def test_bin_slots_fill_layers_and_refuse_what_does_not_fit():
    slots = peer_job.bin_slots(100, 0.05, [(0.0, 0.0, 0.0)])
    assert len({tuple(np.round(s, 6)) for s in slots}) == 100
    assert all(peer_job.FillBinJob.in_bin_box(_at_origin(), s) for s in slots)
    with pytest.raises(ValueError, match="do not fit"):
        peer_job.bin_slots(28, 0.1, [(0.0, 0.0, 0.0)])  # 27 fit: 3 x 3, 3 layers


def _at_origin():
    """A job whose bin 1 stands at the origin (only ``in_bin_box`` is used)."""
    empty = np.zeros(0)
    return peer_job.FillBinJob(empty, empty, empty, (), 0.0, 0, (0, 0, 0), 0.0, (0.0, 0.0, 0.0), 0.1, 0.1)
