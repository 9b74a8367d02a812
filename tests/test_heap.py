"""The heap tuning of sim/heap.py: a running cell's steps reuse their memory instead of
faulting fresh pages in at every step (counted as the process's minor page faults,
which do not depend on the machine's speed or load)."""

from __future__ import annotations

import os
import platform
import subprocess
import sys

import pytest

from omtp_drake.sim import heap

#: fill_bin's controller at work from 4 s to 10 s (the arm moves, a part is carried):
#: the minor page faults of the process meanwhile.
FAULTS = """
import logging, resource
logging.disable(logging.WARNING)
from omtp_drake.tasks.run import TaskRun, prepare
with TaskRun(prepare("fill_bin")) as run:
    run.runtime.advance_to(4.0)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    run.runtime.advance_to(10.0)
    print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def _faults(env: dict[str, str]) -> int:
    done = subprocess.run(
        [sys.executable, "-c", FAULTS], env={**os.environ, **env}, capture_output=True, text=True, check=True
    )
    return int(done.stdout.split()[-1])


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the tuning is glibc's mallopt")
def test_a_running_cell_does_not_fault_its_step_memory_in_again():
    tuned = _faults({})
    # glibc's defaults, chosen by the environment (so tune_heap leaves them).
    defaults = _faults({"MALLOC_MMAP_THRESHOLD_": "131072", "MALLOC_TRIM_THRESHOLD_": "131072"})
    assert tuned < 1000, tuned
    assert defaults > 5 * max(tuned, 100), (tuned, defaults)


def test_the_users_own_thresholds_are_kept(monkeypatch):
    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "131072")
    assert heap.tune_heap() is False
