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
import logging, os, resource
logging.disable(logging.WARNING)
from omtp_drake.sim import heap
from omtp_drake.tasks.run import TaskRun, prepare
with TaskRun(prepare("fill_bin")) as run:
    run.runtime.advance_to(4.0)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    run.runtime.advance_to(10.0)
    faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before
print(heap.tune_heap(), sorted(k for k in os.environ if "MALLOC" in k or "HEAP" in k), faults)
"""


def _faults(env: dict[str, str]) -> tuple[int, str]:
    """The faults, and what the child said (whether it tuned its heap, the environment's choices)."""
    done = subprocess.run(
        [sys.executable, "-c", FAULTS], env={**os.environ, **env}, capture_output=True, text=True, check=True
    )
    line = done.stdout.strip().splitlines()[-1]
    return int(line.split()[-1]), line


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the tuning is glibc's mallopt")
def test_a_running_cell_does_not_fault_its_step_memory_in_again():
    tuned, said = _faults({"MALLOC_TRIM_THRESHOLD_": "65536"})  # Dask's, overridden
    # glibc's defaults (kept by the opt-out), as a Dask worker's environment sets them.
    glibc = {"OMTP_DRAKE_HEAP": "glibc", "MALLOC_TRIM_THRESHOLD_": "65536"}
    defaults, said_defaults = _faults(glibc)
    assert tuned < 1000, (said, said_defaults)
    assert defaults > 5 * max(tuned, 100), (said, said_defaults)


def test_the_opt_out_keeps_glibcs_settings(monkeypatch):
    monkeypatch.setenv(*heap.OPT_OUT)
    assert heap.tune_heap() is False
