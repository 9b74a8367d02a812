"""Shared fixtures (stations are built once per session: building costs ~0.5 s) and
the Hypothesis profiles.

Property tests are derandomized by default: every run, on every machine, draws the
same examples, so the README's test command gives everyone the same result and no
example found elsewhere is replayed from a local database. Exploring new examples
is an opt-in: ``OMTP_HYPOTHESIS=explore pytest ...`` (``bench/bench_fuzz.py`` does
that with many more examples); a failure it finds is kept as an ``@example``.
"""

import compileall
import gc
import logging
import os
import re
import sys
from pathlib import Path

import pytest
from hypothesis import settings

from omtp_drake.errors import UnknownNameError

settings.register_profile("repeatable", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
_PROFILES = ("repeatable", "explore")
_profile = os.environ.get("OMTP_HYPOTHESIS", "repeatable")
if _profile not in _PROFILES:
    raise UnknownNameError("OMTP_HYPOTHESIS profile", _profile, _PROFILES)
settings.load_profile(_profile)

logging.getLogger("drake").setLevel(logging.ERROR)

#: Test files (from tests/) that take the longest, longest first (their tests' seconds in a
#: 2-core `-n 2` run of 2026-11-28: notebooks 64 s in one test, replay renders 44 + 34 + 22 s,
#: grading and batch 10-42 s a test). They run first, each file in its own order, and the rest
#: after them in collection order: with `--dist worksteal` (pyproject.toml's addopts) the two
#: workers share out the short tests at the end and finish together, instead of one waiting
#: for a long test that came last.
SLOW_FIRST = (
    "test_notebooks.py",
    "test_grade_isolation.py",
    "test_replay_render.py",
    "test_batch.py",
    "ros_conformance/test_time.py",
    "test_grade_options.py",
    "test_pick_and_place.py",
    "test_grade_flexbe.py",
    "test_ros_grade.py",
    "test_grade_cache.py",
    "test_memory.py",
    "test_model_view.py",
    "test_ros2_tutorial_robot.py",
    "ros_conformance/test_threads.py",
    "ros_conformance/test_settle.py",
    "test_faults.py",
    "test_heap.py",
    "test_course_factory_states.py",
)
_TESTS = Path(__file__).resolve().parent


def pytest_configure(config):
    """omtp_drake's bytecode is written once, here, before the workers start. Many tests start
    Python processes that import omtp_drake (grade's runs, Dask workers' runners, notebook kernels,
    ROS 2 nodes): where nothing writes bytecode (PYTHONDONTWRITEBYTECODE=1, as in this machine's
    shells) each of them compiled its ~340 modules again (~0.5 CPU s a process). Python reads
    these files whatever that variable says, and checks them against their sources' dates. The
    stand-in packages' launch files are data (read by the launch loader): left as they are."""
    if hasattr(config, "workerinput"):  # an xdist worker: its controller did it
        _share_assertion_rewrites(config)
        return
    compileall.compile_dir(_TESTS.parent / "omtp_drake", quiet=1, rx=re.compile(r"[/\\]standins[/\\]"))


def _share_assertion_rewrites(config):
    """The test files' rewritten asserts are written once and read by every process (pytest
    keeps them in tests/__pycache__, checked against their sources' hashes; where nothing
    writes bytecode, each xdist worker rewrote all ~100 test files again as it collected them:
    ~4.8 of its ~10 CPU s of collection). Both workers write what they rewrite while they
    collect (pytest_collection below); the first (gw0) collects in file order, the second
    first rewrites the files from the last back until it meets one gw0 wrote, then collects
    reading them all. A tree whose files are written rewrites nothing. It uses pytest's own
    functions (private: if one is missing, nothing is done)."""
    if config.getoption("assertmode") != "rewrite" or config.workerinput.get("workerid") != "gw1":
        return
    try:
        from _pytest.assertion import rewrite

        state = config.stash[rewrite.assertstate_key]
        for source in sorted(_TESTS.rglob("test_*.py"), reverse=True):
            pyc = rewrite.get_cache_dir(source) / (source.name[:-3] + rewrite.PYC_TAIL)
            if rewrite._read_pyc(source, pyc) is not None:
                return
            if rewrite.try_makedirs(pyc.parent):
                source_hash, code = rewrite._rewrite_test(source, config)
                rewrite._write_pyc(state, code, source_hash, pyc)
    except (AttributeError, ImportError, KeyError, OSError, SyntaxError):
        return


@pytest.hookimpl(wrapper=True)
def pytest_collection(session):
    """Bytecode is written while the test files are imported (their rewritten asserts, see
    _share_assertion_rewrites), and only then: what the tests import as they run (a student's
    module in a tmp folder) is not written, as before."""
    before = sys.dont_write_bytecode
    sys.dont_write_bytecode = False
    try:
        return (yield)
    finally:
        sys.dont_write_bytecode = before


def pytest_collection_modifyitems(items):
    """The files of SLOW_FIRST first, in its order; a stable sort keeps each file's own order."""
    rank = {name: i for i, name in enumerate(SLOW_FIRST)}

    def key(item):
        try:
            name = Path(item.path).resolve().relative_to(_TESTS).as_posix()
        except ValueError:
            return len(rank)
        return rank.get(name, len(rank))

    items.sort(key=key)


def pytest_collection_finish(session):
    """What collection imported (drake, omtp_drake, the test modules) lives as long as the test
    process: moved out of the garbage collector's generations (``gc.freeze``), as the
    command line does for its own process (omtp_drake.cli), so that a full collection during a
    test does not walk it again. Measured on 4 files (43 tests, one process): time in
    collections 2.4 -> 0.9 s, the process's CPU 63.6 -> 59.9 s."""
    gc.collect()
    gc.freeze()


@pytest.fixture(scope="session")
def factory():
    """The lecture 6 world (both arms, cameras, conveyor, no parts).

    Shared: never add its diagram to another builder (build your own station).
    """
    from omtp_drake.cell.station import build_station  # here: xdist's controller needs neither
    from omtp_drake.scenario import load_scenario

    return build_station(load_scenario("omtp_factory"))

